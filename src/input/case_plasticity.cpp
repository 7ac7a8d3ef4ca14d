// A material's plasticity: the hardening curve as given (a table of tension tests, perfect,
// linear or Ramberg-Osgood) and the unloading. Converted and checked with E and nu by
// Hardening (material/hardening.hpp), which read_materials calls. The keys of the registered
// point laws (material/point_law.hpp) are read here from their declarations.
#include "input/case_sections.hpp"
#include "material/point_law.hpp"

namespace hencky::case_input {

namespace {

/// The curve's keys and the registered laws' (their declarations, read once).
const std::vector<std::string> plasticity_keys = [] {
  std::vector<std::string> k = {"curve", "perfect", "linear", "ramberg_osgood", "unloading"};
  for (const LawDeclaration& law : point_laws())
    for (const LawKey& key : law.keys) k.push_back(key.name);
  return k;
}();
const std::vector<std::string> curve_choices = {"curve", "perfect", "linear", "ramberg_osgood"};
const std::vector<std::string> curve_keys = {"kind", "table"};
const std::vector<std::string> curve_table_keys = {"temperature", "strain", "stress"};
const std::vector<std::string> perfect_keys = {"yield"};
const std::vector<std::string> linear_keys = {"yield", "hardening"};
const std::vector<std::string> ramberg_osgood_keys = {"E", "yield", "alpha", "n"};
const std::vector<std::string> curve_kinds = {"uniaxial", "plastic", "intensity"};
const std::vector<std::string> unloadings = {"elastic", "curve"};

const std::vector<KeySection> sections = [] {
  std::vector<KeySection> s = {
      {"materials[i].plasticity", &plasticity_keys},
      {"materials[i].plasticity.curve", &curve_keys},
      {"materials[i].plasticity.curve.table[j]", &curve_table_keys},
      {"materials[i].plasticity.perfect", &perfect_keys},
      {"materials[i].plasticity.linear", &linear_keys},
      {"materials[i].plasticity.ramberg_osgood", &ramberg_osgood_keys},
  };
  // The laws' groups; the names live as long as the registry.
  static std::vector<std::string> names;
  for (const LawDeclaration& law : point_laws())
    for (const LawKey& key : law.keys)
      names.push_back("materials[i].plasticity." + key.name + "[j]");
  std::size_t i = 0;
  for (const LawDeclaration& law : point_laws())
    for (const LawKey& key : law.keys) s.push_back({names[i++].c_str(), &key.fields});
  return s;
}();

/// `several`: there is more than one table; `converted`: E or nu depends on temperature and the
/// table is converted with them (not the plastic form). Either way the temperature is required.
CurveSpec::Table read_curve_table(const Reader& r, const Val& item, bool several, bool converted,
                                  const CurveSpec::Table* previous) {
  Map m(r, item, curve_table_keys, "a table {temperature: T, strain: [...], stress: [...]}");
  CurveSpec::Table t;
  t.where = r.at(item);
  if (auto x = m.get("temperature")) {
    t.temperature = r.number(*x);
    if (previous && !(t.temperature > previous->temperature))
      r.fail(*x, "the tables' temperatures must be strictly increasing, found " +
                     num(t.temperature) + " after " + num(previous->temperature));
  } else if (several) {
    m.require(r, "temperature",
              "the temperature of this table; it may be left out only when there is one table");
  } else if (converted) {
    m.require(r, "temperature",
              "the temperature of this table: E or nu depends on temperature, and the table is "
              "converted to plastic strains with their values there");
  }
  const Val strain =
      m.require(r, "strain", "the strains of the curve's points, e.g. [0.00114, 0.01]");
  const Val stress =
      m.require(r, "stress", "the stresses of the curve's points in Pa, e.g. [240e6, 260e6]");
  const auto es = r.list(strain, "a list of strains [e1, e2, ...]");
  const auto ss = r.list(stress, "a list of stresses [s1, s2, ...]");
  if (es.empty()) r.fail(strain, "expected at least one point, found an empty list");
  for (std::size_t i = 0; i < es.size(); ++i) {
    t.strain.push_back(r.material_number(es[i]));
    t.point_where.push_back(r.at(es[i]));
    if (i > 0 && !(t.strain[i] > t.strain[i - 1]))
      r.fail(es[i], "strains must be strictly increasing, found " + num(t.strain[i]) + " after " +
                        num(t.strain[i - 1]));
  }
  if (ss.size() != es.size())
    r.fail(stress, "expected " + std::to_string(es.size()) + " stresses (one per strain), found " +
                       std::to_string(ss.size()));
  for (const auto& sv : ss) t.stress.push_back(r.material_number(sv));
  return t;
}

/// curve: {kind: ..., table: [...]}, one table per temperature.
void read_table_curve(const Reader& r, const Val& c, const MaterialSpec& mat, CurveSpec& curve) {
  Map cm(r, c, curve_keys, "a map {kind: uniaxial, table: [...]}");
  curve.kind = CurveSpec::Kind::table;
  const std::string kind = r.choice(
      cm.require(r, "kind",
                 "how the table is read: uniaxial (stress vs total strain of a tension test), "
                 "plastic (stress vs plastic strain) or intensity (stress vs strain intensity)"),
      curve_kinds, "curve kind");
  curve.form = kind == "uniaxial"  ? CurveSpec::Form::uniaxial
               : kind == "plastic" ? CurveSpec::Form::plastic
                                   : CurveSpec::Form::intensity;
  const Val tv = cm.require(
      r, "table", "one entry per temperature: [{temperature: 20, strain: [...], stress: [...]}]");
  const auto items =
      r.entries(tv, "a list of tables [{temperature: T, strain: [...], stress: [...]}]");
  if (items.empty()) r.fail(tv, "expected at least one table, found an empty list");
  const bool converted =
      curve.form != CurveSpec::Form::plastic && !(mat.E.is_constant() && mat.nu.is_constant());
  for (const auto& item : items)
    curve.tables.push_back(read_curve_table(r, item, items.size() > 1, converted,
                                            curve.tables.empty() ? nullptr : &curve.tables.back()));
}

PropertyTable read_yield(const Reader& r, const Map& cm) {
  return read_property(r,
                       cm.require(r, "yield", "the initial yield stress in Pa, e.g. yield: 240e6"),
                       "yield", Property::yield);
}

/// ramberg_osgood: {E: ..., yield: ..., alpha: ..., n: ...}.
void read_ramberg_osgood(const Reader& r, const Val& c, CurveSpec& curve) {
  Map cm(r, c, ramberg_osgood_keys, "a map {E: 2e11, yield: 240e6, alpha: 0.002, n: 10}");
  curve.kind = CurveSpec::Kind::ramberg_osgood;
  const Val ro_E = cm.require(
      r, "E", "the Young's modulus of the Ramberg-Osgood fit in Pa (usually the material's E)");
  curve.ro_E = r.positive(ro_E);
  r.material_number(ro_E);
  curve.yield = read_yield(r, cm);
  const Val ro_alpha = cm.require(r, "alpha", "the Ramberg-Osgood factor, e.g. alpha: 0.002");
  curve.ro_alpha = r.positive(ro_alpha);
  r.material_number(ro_alpha);
  const Val n = cm.require(r, "n", "the Ramberg-Osgood exponent (> 1), e.g. n: 10");
  curve.ro_n = r.number(n);
  if (!(curve.ro_n > 1)) r.fail(n, "expected an exponent n > 1, found " + num(curve.ro_n));
}

/// The keys of the registered point laws under `plasticity:` (at most one law's).
void read_law_keys(const Reader& r, const Map& m, PlasticitySpec& p) {
  for (const LawDeclaration& law : point_laws())
    for (const LawKey& key : law.keys) {
      const auto v = m.get(key.name);
      if (!v) continue;
      if (!p.law.law.empty() && p.law.law != law.name)
        r.fail(*v,
               "give one point law, found keys of both '" + p.law.law + "' and '" + law.name + "'");
      p.law.law = law.name;
      p.law.where = r.at(*v);
      std::string example = "{";
      for (const auto& f : key.fields) example += (example.size() > 1 ? ", " : "") + f + ": ...";
      example += "}";
      const auto items =
          r.entries(*v, "a list of groups [" + example + ", ...] (" + key.unit + ")");
      if (items.empty())
        r.fail(*v, "expected at least one group " + example + ", found an empty list");
      auto& groups = p.law.keys[key.name];
      for (const auto& item : items) {
        Map g(r, item, key.fields, "a group " + example);
        LawParameters::Group group;
        for (const auto& f : key.fields)
          group[f] = read_property(r, g.require(r, f, "the field '" + f + "' (" + key.unit + ")"),
                                   key.name + "." + f, Property::any);
        groups.push_back(std::move(group));
      }
    }
}

}  // namespace

std::span<const KeySection> plasticity_sections() {
  return sections;
}

PlasticitySpec read_plasticity(const Reader& r, const Val& v, const MaterialSpec& mat) {
  Map m(r, v, plasticity_keys,
        "a map like {curve: {kind: uniaxial, table: [...]}} or {perfect: {yield: 240e6}}");
  PlasticitySpec p;
  p.where = r.at(v);
  std::vector<std::string> given;
  for (const auto& k : curve_choices)
    if (m.has(k)) given.push_back(k);
  if (given.empty())
    r.fail(v,
           "plasticity needs a hardening curve: one of 'curve', 'perfect', 'linear', "
           "'ramberg_osgood' (e.g. perfect: {yield: 240e6})");
  if (given.size() > 1)
    throw InputError(
        r.at(m.key_mark(given[1]), m.get(given[1])->path),
        "give one hardening curve, found both '" + given[0] + "' and '" + given[1] + "'");
  const Val c = *m.get(given[0]);
  CurveSpec& curve = p.curve;
  curve.where = r.at(c);
  if (given[0] == "curve") {
    read_table_curve(r, c, mat, curve);
  } else if (given[0] == "perfect") {
    Map cm(r, c, perfect_keys, "a map {yield: 240e6}");
    curve.kind = CurveSpec::Kind::perfect;
    curve.yield = read_yield(r, cm);
  } else if (given[0] == "linear") {
    Map cm(r, c, linear_keys, "a map {yield: 240e6, hardening: 2e9}");
    curve.kind = CurveSpec::Kind::linear;
    curve.yield = read_yield(r, cm);
    curve.hardening = read_property(
        r,
        cm.require(
            r, "hardening",
            "the plastic modulus dσ/dε^p in Pa, e.g. hardening: 2e9 (0: perfect plasticity)"),
        "hardening", Property::hardening);
  } else {
    read_ramberg_osgood(r, c, curve);
  }
  read_law_keys(r, m, p);
  if (auto u = m.get("unloading"))
    p.unloading = r.choice(*u, unloadings, "unloading") == "elastic"
                      ? PlasticitySpec::Unloading::elastic
                      : PlasticitySpec::Unloading::curve;
  return p;
}

}  // namespace hencky::case_input
