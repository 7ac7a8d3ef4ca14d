#include "input/case_reader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "core/suggest.hpp"
#include "material/elastic.hpp"
#include "material/hardening.hpp"
#include "parallel/mpi.hpp"

namespace hencky {

namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------------------------
// Keys of every map in the case file. Later versions' keys are known (never "unknown key").

const std::vector<std::string> top_keys = {"title",       "mesh",     "materials",
                                           "temperature", "boundary", "body_force",
                                           "contact",     "solver",   "output"};
const std::vector<std::string> mesh_keys = {"file", "order", "scale"};
const std::vector<std::string> material_keys = {"name", "regions", "E",
                                                "nu",   "alpha",   "plasticity"};
const std::vector<std::string> table_keys = {"temperature", "value"};
const std::vector<std::string> plasticity_keys = {"curve", "perfect", "linear", "ramberg_osgood",
                                                  "unloading"};
const std::vector<std::string> curve_choices = {"curve", "perfect", "linear", "ramberg_osgood"};
const std::vector<std::string> curve_keys = {"kind", "table"};
const std::vector<std::string> curve_table_keys = {"temperature", "strain", "stress"};
const std::vector<std::string> perfect_keys = {"yield"};
const std::vector<std::string> linear_keys = {"yield", "hardening"};
const std::vector<std::string> ramberg_osgood_keys = {"E", "yield", "alpha", "n"};
const std::vector<std::string> curve_kinds = {"uniaxial", "plastic", "intensity"};
const std::vector<std::string> unloadings = {"elastic", "curve"};
const std::vector<std::string> temperature_keys = {"reference", "field"};
const std::vector<std::string> field_file_keys = {"file"};
const std::vector<std::string> boundary_keys = {"region", "displacement", "pressure", "traction",
                                                "force"};
const std::vector<std::string> conditions = {"displacement", "pressure", "traction", "force"};
const std::vector<std::string> xyz_keys = {"x", "y", "z"};
const std::vector<std::string> solver_keys = {
    "scheme",         "curve_form",      "steps",      "end",          "times",
    "max_iterations", "tolerance",       "relaxation", "correction",   "cutback",
    "linear",         "mechanism_limit", "predictor",  "acceleration", "petsc_options"};
const std::vector<std::string> contact_keys = {"name",   "nodes",     "surface",
                                               "motion", "stiffness", "penetration"};
const std::vector<std::string> surface_kinds = {"plane", "sphere", "cylinder", "mesh"};
const std::vector<std::string> plane_keys = {"point", "normal"};
const std::vector<std::string> sphere_keys = {"center", "radius"};
const std::vector<std::string> cylinder_keys = {"point", "axis", "radius"};
const std::vector<std::string> stl_keys = {"file", "scale"};
const std::vector<std::string> output_keys = {"dir", "every", "probes", "reactions"};
const std::vector<std::string> probe_keys = {"name", "point"};
const std::vector<std::string> schemes = {"newton",         "variable-stiffness",
                                          "initial-strain", "initial-strain-stiffness",
                                          "initial-stress", "initial-stress-stiffness"};
const std::vector<std::string> curve_forms = {"stress", "strain"};
const std::vector<std::string> predictors = {"extrapolate", "none"};
const std::vector<std::string> accelerations = {"none", "anderson"};
const std::vector<std::string> linear_solvers = {"direct", "iterative", "petsc"};

struct Section {
  const char* name;
  const std::vector<std::string>* keys;
};
const Section sections[] = {
    {"the top level", &top_keys},
    {"mesh", &mesh_keys},
    {"materials[i]", &material_keys},
    {"materials[i].plasticity", &plasticity_keys},
    {"materials[i].plasticity.curve", &curve_keys},
    {"materials[i].plasticity.curve.table[j]", &curve_table_keys},
    {"materials[i].plasticity.perfect", &perfect_keys},
    {"materials[i].plasticity.linear", &linear_keys},
    {"materials[i].plasticity.ramberg_osgood", &ramberg_osgood_keys},
    {"temperature", &temperature_keys},
    {"boundary[i]", &boundary_keys},
    {"boundary[i].displacement", &xyz_keys},
    {"contact[i]", &contact_keys},
    {"contact[i].surface", &surface_kinds},
    {"contact[i].surface.plane", &plane_keys},
    {"contact[i].surface.sphere", &sphere_keys},
    {"contact[i].surface.cylinder", &cylinder_keys},
    {"contact[i].surface.mesh", &stl_keys},
    {"solver", &solver_keys},
    {"output", &output_keys},
    {"output.probes[i]", &probe_keys},
};

/// "'steps' is a key of 'solver'" when an unknown key is valid in another section.
std::string belongs_elsewhere(const std::string& key, const std::vector<std::string>* here) {
  std::vector<std::string> where;
  for (const auto& s : sections)
    if (s.keys != here && std::find(s.keys->begin(), s.keys->end(), key) != s.keys->end())
      where.emplace_back(s.name);
  if (where.empty()) return {};
  std::string s = "'" + key + "' is a key of ";
  for (std::size_t i = 0; i < where.size(); ++i)
    s += (i ? (i + 1 == where.size() ? " and " : ", ") : "") +
         (where[i] == "the top level" ? where[i] : "'" + where[i] + "'");
  return s;
}

// ---------------------------------------------------------------------------------------------
// Text helpers

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

bool parse_double(const std::string& text, double& v) {
  const std::string s = trim(text);
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  auto [p, ec] = std::from_chars(b, e, v);
  return ec == std::errc() && p == e;
}

bool parse_long(const std::string& text, long& v) {
  const std::string s = trim(text);
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  auto [p, ec] = std::from_chars(b, e, v);
  return ec == std::errc() && p == e;
}

std::string num(double v) {
  char buf[64];
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, p) : std::to_string(v);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string child_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}
std::string index_path(const std::string& parent, std::size_t i) {
  return parent + "[" + std::to_string(i) + "]";
}

/// What a node is, for "found ..." in messages.
std::string describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Scalar: {
      std::string s = n.Scalar();
      if (s.size() > 60) s = s.substr(0, 57) + "...";
      return "'" + s + "'";
    }
    default:
      return "nothing";
  }
}

// ---------------------------------------------------------------------------------------------
// A node with its dotted key path and the best location to report it at.

struct Val {
  YAML::Node node;
  std::string path;
  YAML::Mark mark;
};

class Reader {
 public:
  Reader(std::string label, fs::path dir) : label_(std::move(label)), dir_(std::move(dir)) {}

  const std::string& label() const { return label_; }
  const fs::path& dir() const { return dir_; }

  SourceLocation at(const YAML::Mark& m, const std::string& key) const {
    SourceLocation w;
    w.file = label_;
    if (m.line >= 0) w.line = m.line + 1;
    if (m.column >= 0 && m.line >= 0) w.column = m.column + 1;
    w.key = key;
    return w;
  }
  SourceLocation at(const Val& v) const { return at(v.mark, v.path); }
  [[noreturn]] void fail(const Val& v, const std::string& msg) const {
    throw InputError(at(v), msg);
  }

  double number(const Val& v) const {
    if (!v.node.IsScalar()) fail(v, "expected a number, found " + describe(v.node));
    double x = 0;
    if (!parse_double(v.node.Scalar(), x)) fail(v, "expected a number, found " + describe(v.node));
    if (!std::isfinite(x)) fail(v, "expected a finite number, found " + describe(v.node));
    return x;
  }

  long integer(const Val& v) const {
    if (!v.node.IsScalar()) fail(v, "expected a whole number, found " + describe(v.node));
    long x = 0;
    if (!parse_long(v.node.Scalar(), x))
      fail(v, "expected a whole number, found " + describe(v.node));
    return x;
  }

  int integer_at_least(const Val& v, long min) const {
    const long x = integer(v);
    if (x < min)
      fail(v, "expected a whole number >= " + std::to_string(min) + ", found " + std::to_string(x));
    if (x > 1000000000L)
      fail(v, "expected a whole number <= 1000000000, found " + std::to_string(x));
    return static_cast<int>(x);
  }

  double positive(const Val& v) const {
    const double x = number(v);
    if (!(x > 0)) fail(v, "expected a number > 0, found " + num(x));
    return x;
  }

  /// A number of a material's data (E, nu, alpha, a table's values, a curve's points):
  /// finite, and not subnormal (0 < |x| < DBL_MIN, e.g. 1e-310), which the stiffness and
  /// stress arithmetic cannot carry: it has lost precision already and its products vanish.
  double material_number(const Val& v) const {
    const double x = number(v);
    if (x != 0 && std::abs(x) < std::numeric_limits<double>::min())
      fail(v, "expected 0 or a number of magnitude >= " + num(std::numeric_limits<double>::min()) +
                  ", found " + describe(v.node) +
                  " (a subnormal number, too small for the stiffness and stress arithmetic)");
    return x;
  }

  std::string string(const Val& v, const char* what = "a name") const {
    if (!v.node.IsScalar())
      fail(v, std::string("expected ") + what + ", found " + describe(v.node));
    std::string s = trim(v.node.Scalar());
    if (s.empty()) fail(v, std::string("expected ") + what + ", found an empty string");
    return s;
  }

  Expression expression(const Val& v) const {
    if (!v.node.IsScalar())
      fail(v, "expected a number or an expression in x, y, z, t (e.g. \"100e6*t\"), found " +
                  describe(v.node));
    return Expression::parse(v.node.Scalar(), at(v));
  }

  std::vector<Val> list(const Val& v, const std::string& what = "a list [a, b, ...]") const {
    if (!v.node.IsSequence()) fail(v, "expected " + what + ", found " + describe(v.node));
    std::vector<Val> items;
    for (std::size_t i = 0; i < v.node.size(); ++i) {
      YAML::Node n = v.node[i];
      const YAML::Mark m = n.IsNull() || n.Mark().line < 0 ? v.mark : n.Mark();
      items.push_back({n, index_path(v.path, i), m});
    }
    return items;
  }

  std::vector<Val> list3(const Val& v, const char* what) const {
    auto items = list(v, std::string("a list of 3 ") + what + " [x, y, z]");
    if (items.size() != 3)
      fail(v, std::string("expected a list of 3 ") + what + " [x, y, z], found a list of " +
                  std::to_string(items.size()));
    return items;
  }

  std::array<Expression, 3> expression3(const Val& v) const {
    auto items = list3(v, "numbers or expressions");
    return {expression(items[0]), expression(items[1]), expression(items[2])};
  }

  Vec3 vec3(const Val& v) const {
    auto items = list3(v, "numbers");
    return {number(items[0]), number(items[1]), number(items[2])};
  }

  /// A list of names, or one name (shorthand for a list of one).
  std::vector<Val> names(const Val& v) const {
    if (v.node.IsScalar()) return {v};
    auto items = list(v, "a list of names [a, b, ...]");
    if (items.empty()) fail(v, "expected a list of names [a, b, ...], found an empty list");
    return items;
  }

  std::string choice(const Val& v, const std::vector<std::string>& options,
                     const char* what) const {
    const std::string s = string(v, "a name");
    if (std::find(options.begin(), options.end(), s) != options.end()) return s;
    fail(v, "unknown " + std::string(what) + " '" + s + "'; " +
                suggestion(s, options, std::string(what) + "s"));
  }

  fs::path resolve(const std::string& p) const {
    fs::path path(p);
    if (path.is_relative()) path = dir_ / path;
    return path.lexically_normal();
  }

 private:
  std::string label_;
  fs::path dir_;
};

/// A YAML map whose keys were checked: no unknown keys, no duplicates.
class Map {
 public:
  Map(const Reader& r, const Val& v, const std::vector<std::string>& allowed,
      const std::string& what = "a map of keys")
      : self_(v) {
    if (!v.node.IsMap()) r.fail(v, "expected " + what + ", found " + describe(v.node));
    for (auto it = v.node.begin(); it != v.node.end(); ++it) {
      const YAML::Node key = it->first;
      const YAML::Mark key_mark = key.Mark();
      if (!key.IsScalar())
        throw InputError(r.at(key_mark, v.path), "expected a key name, found " + describe(key));
      const std::string name = key.Scalar();
      const std::string path = child_path(v.path, name);
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
        std::string msg = "unknown key '" + name + "'";
        const std::string hint = did_you_mean(name, allowed);
        if (!hint.empty())
          msg += "; " + hint;
        else if (auto other = belongs_elsewhere(name, &allowed); !other.empty())
          msg += "; " + other;
        msg += " (valid keys here: " + name_list(allowed) + ")";
        throw InputError(r.at(key_mark, path), msg);
      }
      if (auto prev = entries_.find(name); prev != entries_.end())
        throw InputError(r.at(key_mark, path),
                         "duplicate key '" + name + "' (first given at line " +
                             std::to_string(prev->second.key_mark.line + 1) + ")");
      const YAML::Node value = it->second;
      const YAML::Mark m = value.IsNull() || value.Mark().line < 0 ? key_mark : value.Mark();
      entries_.emplace(name, Entry{Val{value, path, m}, key_mark});
    }
  }

  bool has(const std::string& key) const { return entries_.count(key) != 0; }
  std::optional<Val> get(const std::string& key) const {
    auto it = entries_.find(key);
    if (it == entries_.end()) return std::nullopt;
    return it->second.val;
  }
  YAML::Mark key_mark(const std::string& key) const { return entries_.at(key).key_mark; }
  Val require(const Reader& r, const std::string& key, const std::string& hint) const {
    auto v = get(key);
    if (!v) {
      std::string msg = "missing key '" + key + "'";
      if (!hint.empty()) msg += " (" + hint + ")";
      throw InputError(r.at(self_.mark, child_path(self_.path, key)), msg);
    }
    return *v;
  }
  const Val& self() const { return self_; }

 private:
  struct Entry {
    Val val;
    YAML::Mark key_mark;
  };
  Val self_;
  std::map<std::string, Entry> entries_;
};

// ---------------------------------------------------------------------------------------------
// Sections

MeshSpec read_mesh(const Reader& r, const Val& v) {
  Map m(r, v, mesh_keys, "a map like {file: part.msh}");
  MeshSpec mesh;
  const Val file = m.require(r, "file", "the Gmsh mesh, e.g. file: part.msh");
  mesh.where = r.at(file);
  const std::string name = r.string(file, "a file name");
  mesh.file = r.resolve(name);
  const std::string ext = lower(mesh.file.extension().string());
  if (ext != ".msh" && ext != ".geo")
    r.fail(file, "expected a Gmsh mesh (.msh) or geometry (.geo) file, found '" + name + "'");
  std::error_code ec;
  if (!fs::exists(mesh.file, ec))
    r.fail(file, "mesh file not found: " + mesh.file.string() +
                     " (relative paths are taken from the case file's folder)");
  if (!fs::is_regular_file(mesh.file, ec))
    r.fail(file, "expected a mesh file, found a directory or special file: " + mesh.file.string());
  if (auto o = m.get("order")) {
    const long order = r.integer(*o);
    if (order != 1 && order != 2) r.fail(*o, "expected 1 or 2, found " + std::to_string(order));
    mesh.order = static_cast<int>(order);
  }
  if (auto s = m.get("scale")) mesh.scale = r.positive(*s);
  return mesh;
}

enum class Property { E, nu, alpha, yield, hardening };

void check_property(const Reader& r, const Val& v, Property p, const std::string& what, double x) {
  switch (p) {
    case Property::E:
      if (!(x > 0)) r.fail(v, what + " must be > 0, found " + num(x));
      break;
    case Property::nu:
      if (!(x > -1.0 && x < 0.5))
        r.fail(v, what +
                      " must satisfy -1 < nu < 0.5 (0.5 is incompressible, which this "
                      "displacement formulation cannot solve), found " +
                      num(x));
      break;
    case Property::yield:
      if (!(x > 0)) r.fail(v, what + " must be > 0, found " + num(x));
      break;
    case Property::alpha:
    case Property::hardening:  // may be negative (softening); > -3G is checked with E and nu
      break;
  }
}

PropertyTable read_property(const Reader& r, const Val& v, const std::string& name, Property p) {
  PropertyTable t;
  t.where = r.at(v);
  if (v.node.IsScalar()) {
    t.value = {r.material_number(v)};
    check_property(r, v, p, name, t.value[0]);
    return t;
  }
  if (!v.node.IsMap())
    r.fail(v, "expected a number or a table {temperature: [...], value: [...]}, found " +
                  describe(v.node));
  Map m(r, v, table_keys);
  const Val temp = m.require(r, "temperature", "the table's temperatures, e.g. [20, 500]");
  const Val val = m.require(r, "value", "the values at those temperatures");
  const auto ts = r.list(temp, "a list of temperatures [T1, T2, ...]");
  const auto vs = r.list(val, "a list of values [v1, v2, ...]");
  if (ts.empty()) r.fail(temp, "expected at least one temperature, found an empty list");
  for (std::size_t i = 0; i < ts.size(); ++i) {
    t.temperature.push_back(r.number(ts[i]));
    if (i > 0 && !(t.temperature[i] > t.temperature[i - 1]))
      r.fail(ts[i], "temperatures must be strictly increasing, found " + num(t.temperature[i]) +
                        " after " + num(t.temperature[i - 1]));
  }
  if (vs.size() != ts.size())
    r.fail(val, "expected " + std::to_string(ts.size()) + " values (one per temperature), found " +
                    std::to_string(vs.size()));
  for (std::size_t i = 0; i < vs.size(); ++i) {
    t.value.push_back(r.material_number(vs[i]));
    check_property(r, vs[i], p, name, t.value[i]);
  }
  return t;
}

/// E and nu whose stiffness or compliance leaves the range of floating point (E = 1e308 with
/// nu = 0.3 has a finite E but an infinite E/(1 − 2nu)): checked at every temperature of
/// their tables, where the extremes of these monotone functions of E and nu lie.
void check_elastic_range(const MaterialSpec& mat) {
  std::vector<double> ts = {0.0};
  for (const PropertyTable* p : {&mat.E, &mat.nu})
    ts.insert(ts.end(), p->temperature.begin(), p->temperature.end());
  for (double T : ts) {
    const ElasticConstants k{mat.E(T), mat.nu(T), 0.0};
    const std::pair<const char*, double> parts[] = {
        {"the shear modulus G = E/(2(1 + nu))", k.shear_modulus()},
        {"the Lame constant lambda = E nu/((1 + nu)(1 - 2nu))", k.lame_lambda()},
        {"the bulk stiffness E/(1 - 2nu)", k.E / (1 - 2 * k.nu)},
        {"the compliance 2(1 + nu)/E", 2 * (1 + k.nu) / k.E}};
    for (const auto& [what, value] : parts)
      if (!std::isfinite(value))
        throw InputError(
            mat.E.where,
            "E = " + num(k.E) + " with nu = " + num(k.nu) +
                (mat.E.is_constant() && mat.nu.is_constant() ? std::string()
                                                             : " (at temperature " + num(T) + ")") +
                " gives " + what + " = " + num(value) +
                ", beyond the range of floating point; choose units that keep the "
                "material's numbers moderate (e.g. MPa and mm)");
  }
}

// ---------------------------------------------------------------------------------------------
// Plasticity: the hardening curve as given; converted and checked with E and nu by Hardening.

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
  const auto yield = [&](const Map& cm) {
    return read_property(
        r, cm.require(r, "yield", "the initial yield stress in Pa, e.g. yield: 240e6"), "yield",
        Property::yield);
  };
  if (given[0] == "curve") {
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
    if (tv.node.IsMap())
      r.fail(tv,
             "expected a list of tables (start each entry with '- ' or write [{...}]), found a "
             "map");
    const auto items =
        r.list(tv, "a list of tables [{temperature: T, strain: [...], stress: [...]}]");
    if (items.empty()) r.fail(tv, "expected at least one table, found an empty list");
    const bool converted =
        curve.form != CurveSpec::Form::plastic && !(mat.E.is_constant() && mat.nu.is_constant());
    for (const auto& item : items)
      curve.tables.push_back(
          read_curve_table(r, item, items.size() > 1, converted,
                           curve.tables.empty() ? nullptr : &curve.tables.back()));
  } else if (given[0] == "perfect") {
    Map cm(r, c, perfect_keys, "a map {yield: 240e6}");
    curve.kind = CurveSpec::Kind::perfect;
    curve.yield = yield(cm);
  } else if (given[0] == "linear") {
    Map cm(r, c, linear_keys, "a map {yield: 240e6, hardening: 2e9}");
    curve.kind = CurveSpec::Kind::linear;
    curve.yield = yield(cm);
    curve.hardening = read_property(
        r,
        cm.require(
            r, "hardening",
            "the plastic modulus dσ/dε^p in Pa, e.g. hardening: 2e9 (0: perfect plasticity)"),
        "hardening", Property::hardening);
  } else {
    Map cm(r, c, ramberg_osgood_keys, "a map {E: 2e11, yield: 240e6, alpha: 0.002, n: 10}");
    curve.kind = CurveSpec::Kind::ramberg_osgood;
    const Val ro_E = cm.require(
        r, "E", "the Young's modulus of the Ramberg-Osgood fit in Pa (usually the material's E)");
    curve.ro_E = r.positive(ro_E);
    r.material_number(ro_E);
    curve.yield = yield(cm);
    const Val ro_alpha = cm.require(r, "alpha", "the Ramberg-Osgood factor, e.g. alpha: 0.002");
    curve.ro_alpha = r.positive(ro_alpha);
    r.material_number(ro_alpha);
    const Val n = cm.require(r, "n", "the Ramberg-Osgood exponent (> 1), e.g. n: 10");
    curve.ro_n = r.number(n);
    if (!(curve.ro_n > 1)) r.fail(n, "expected an exponent n > 1, found " + num(curve.ro_n));
  }
  if (auto u = m.get("unloading"))
    p.unloading = r.choice(*u, unloadings, "unloading") == "elastic"
                      ? PlasticitySpec::Unloading::elastic
                      : PlasticitySpec::Unloading::curve;
  return p;
}

std::vector<MaterialSpec> read_materials(const Reader& r, const Val& v, bool has_temperature) {
  if (v.node.IsMap())
    r.fail(v, "expected a list of materials (start each entry with '- '), found a map");
  const auto items = r.list(v, "a list of materials");
  if (items.empty()) r.fail(v, "expected at least one material, found an empty list");
  std::vector<MaterialSpec> out;
  std::map<std::string, std::size_t> names;
  std::map<std::string, std::size_t> region_owner;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Val& item = items[i];
    Map m(r, item, material_keys, "a material {name: ..., E: ..., nu: ..., alpha: ...}");
    MaterialSpec mat;
    mat.where = r.at(item);
    if (auto n = m.get("name")) {
      mat.name = r.string(*n);
      if (auto prev = names.find(mat.name); prev != names.end())
        r.fail(*n, "material name '" + mat.name + "' is already used by materials[" +
                       std::to_string(prev->second) + "]");
    } else {
      mat.name = "material" + std::to_string(i);
    }
    names.emplace(mat.name, i);
    if (auto regs = m.get("regions")) {
      for (const Val& rv : r.names(*regs)) {
        const std::string reg = r.string(rv, "a region name");
        if (auto prev = region_owner.find(reg); prev != region_owner.end()) {
          if (prev->second == i) r.fail(rv, "region '" + reg + "' is listed twice");
          r.fail(rv, "region '" + reg + "' is already given to material '" +
                         out[prev->second].name + "' (materials[" + std::to_string(prev->second) +
                         "]); a region has one material");
        }
        mat.regions.push_back(reg);
        mat.region_where.push_back(r.at(rv));
        region_owner.emplace(reg, i);
      }
    } else if (items.size() > 1) {
      r.fail(item, "material '" + mat.name +
                       "' needs 'regions' (the Gmsh physical volumes it "
                       "fills): it may be left out only when there is one material");
    }
    mat.E = read_property(r, m.require(r, "E", "Young's modulus in Pa, e.g. E: 2.1e11"), "E",
                          Property::E);
    mat.nu =
        read_property(r, m.require(r, "nu", "Poisson's ratio, e.g. nu: 0.3"), "nu", Property::nu);
    check_elastic_range(mat);
    if (auto a = m.get("alpha")) {
      mat.alpha = read_property(r, *a, "alpha", Property::alpha);
    } else if (has_temperature) {
      m.require(r, "alpha",
                "the thermal expansion coefficient in 1/K, e.g. alpha: 1.2e-5; "
                "it is required because the case has a temperature section");
    } else {
      mat.alpha.value = {0.0};
      mat.alpha.where = mat.where;
    }
    if (auto pl = m.get("plasticity")) {
      mat.plasticity = read_plasticity(r, *pl, mat);
      // Converting the curve needs E and nu: done here only to report a bad curve now (for
      // `hencky check`); the model builds its own.
      (void)Hardening(*mat.plasticity, mat.E, mat.nu);
    }
    out.push_back(std::move(mat));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Temperature

struct CsvCell {
  std::string text;
  int column;  // 1-based
};

std::vector<CsvCell> split_csv(const std::string& line) {
  std::vector<CsvCell> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    const std::string raw =
        line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::size_t lead = raw.find_first_not_of(" \t");
    cells.push_back(
        {trim(raw), static_cast<int>(start + (lead == std::string::npos ? 0 : lead)) + 1});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
}

TemperatureFile read_temperature_csv(const Reader& r, const Val& v) {
  TemperatureFile tf;
  const std::string name = r.string(v, "a file name");
  tf.path = r.resolve(name);
  std::error_code ec;
  if (!fs::is_regular_file(tf.path, ec))
    r.fail(v, "temperature file not found: " + tf.path.string() +
                  " (relative paths are taken from the case file's folder)");
  std::ifstream in(tf.path);
  if (!in) r.fail(v, "cannot open the temperature file " + tf.path.string());

  const std::string label = tf.path.string();
  auto fail_at = [&](int line, int column, const std::string& msg) {
    throw InputError(SourceLocation{label, line, column, v.path}, msg);
  };

  std::string line;
  int line_no = 0;
  bool header = false;
  std::size_t n_cols = 0;
  std::map<long, int> seen;  // node tag -> line
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
    if (trim(line).empty()) continue;
    const auto cells = split_csv(line);
    if (!header) {
      if (lower(cells[0].text) != "node")
        fail_at(line_no, cells[0].column,
                "expected the header row 'node,<time 1>,<time 2>,...', found '" + cells[0].text +
                    "' as the first column name");
      if (cells.size() < 2)
        fail_at(line_no, 0, "the header row lists no times: expected 'node,<time 1>,<time 2>,...'");
      for (std::size_t j = 1; j < cells.size(); ++j) {
        double t = 0;
        if (!parse_double(cells[j].text, t) || !std::isfinite(t))
          fail_at(line_no, cells[j].column,
                  "expected a time in the header row, found '" + cells[j].text + "'");
        if (!tf.times.empty() && !(t > tf.times.back()))
          fail_at(line_no, cells[j].column,
                  "the times in the header row must be strictly increasing, found " + num(t) +
                      " after " + num(tf.times.back()));
        tf.times.push_back(t);
      }
      n_cols = cells.size();
      header = true;
      continue;
    }
    if (cells.size() != n_cols)
      fail_at(line_no, 0,
              "expected " + std::to_string(n_cols) +
                  " values (the node tag, then one per time), found " +
                  std::to_string(cells.size()));
    long tag = 0;
    if (!parse_long(cells[0].text, tag) || tag <= 0)
      fail_at(line_no, cells[0].column,
              "expected a node tag (a whole number > 0), found '" + cells[0].text + "'");
    if (auto prev = seen.find(tag); prev != seen.end())
      fail_at(line_no, cells[0].column,
              "node " + std::to_string(tag) + " is listed twice (first at line " +
                  std::to_string(prev->second) + ")");
    seen.emplace(tag, line_no);
    tf.node_tags.push_back(tag);
    for (std::size_t j = 1; j < cells.size(); ++j) {
      double T = 0;
      if (!parse_double(cells[j].text, T) || !std::isfinite(T))
        fail_at(line_no, cells[j].column,
                "expected a temperature (a number), found '" + cells[j].text + "'");
      tf.values.push_back(T);
    }
  }
  if (!header)
    fail_at(0, 0,
            "the temperature file is empty: expected 'node,<time 1>,...' then one row per node");
  if (tf.node_tags.empty())
    fail_at(line_no, 0, "the temperature file has a header but no node rows");
  return tf;
}

TemperatureSpec read_temperature(const Reader& r, const Val& v) {
  Map m(r, v, temperature_keys, "a map {reference: ..., field: ...}");
  TemperatureSpec t;
  t.given = true;
  t.where = r.at(v);
  const Val reference = m.require(
      r, "reference", "the stress-free temperature T_ref; it is never guessed, e.g. reference: 20");
  t.reference = r.number(reference);
  t.reference_where = r.at(reference);
  const Val f = m.require(
      r, "field", "the temperature: a number, an expression in x, y, z, t or {file: temps.csv}");
  t.field_where = r.at(f);
  if (f.node.IsMap()) {
    Map fm(r, f, field_file_keys, "{file: temps.csv}");
    const Val file = fm.require(r, "file", "the CSV file with the nodal temperatures");
    t.field_where = r.at(file);
    t.file = read_temperature_csv(r, file);
  } else if (f.node.IsScalar()) {
    t.field = r.expression(f);
  } else {
    r.fail(f, "expected a number, an expression in x, y, z, t or {file: temps.csv}, found " +
                  describe(f.node));
  }
  return t;
}

// ---------------------------------------------------------------------------------------------
// Boundary conditions

std::vector<BoundarySpec> read_boundary(const Reader& r, const Val& v) {
  if (v.node.IsMap())
    r.fail(v, "expected a list of conditions (start each entry with '- '), found a map");
  std::vector<BoundarySpec> out;
  std::map<std::pair<std::string, int>, std::size_t> prescribed;  // (region, axis) -> entry
  const auto items = r.list(v, "a list of conditions");
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Val& item = items[i];
    Map m(r, item, boundary_keys,
          "a condition {region: ..., displacement|pressure|traction|force: ...}");
    BoundarySpec b;
    const Val region = m.require(r, "region", "the Gmsh physical group the condition acts on");
    if (region.node.IsSequence())
      r.fail(region, "expected one region name, found a list; write one entry per region");
    b.region = r.string(region, "a region name");
    b.where = r.at(region);

    std::vector<std::string> given;
    for (const auto& c : conditions)
      if (m.has(c)) given.push_back(c);
    if (given.empty())
      r.fail(item, "boundary entry for region '" + b.region +
                       "' has no condition: expected one of 'displacement', 'pressure', "
                       "'traction', 'force'");
    if (given.size() > 1) {
      const Val second = *m.get(given[1]);
      throw InputError(r.at(m.key_mark(given[1]), second.path),
                       "a boundary entry has one condition, found both '" + given[0] + "' and '" +
                           given[1] + "'; write another entry for the same region");
    }
    const Val c = *m.get(given[0]);
    if (given[0] == "displacement") {
      b.kind = BoundaryKind::displacement;
      Map d(r, c, xyz_keys, "a map of components like {x: 0, z: \"0.001*t\"}");
      bool any = false;
      for (int k = 0; k < 3; ++k) {
        auto comp = d.get(xyz_keys[k]);
        if (!comp) continue;
        any = true;
        b.components[k] = r.expression(*comp);
        const auto key = std::make_pair(b.region, k);
        if (auto prev = prescribed.find(key); prev != prescribed.end())
          r.fail(*comp, "the " + xyz_keys[k] + " displacement of region '" + b.region +
                            "' is already prescribed by boundary[" + std::to_string(prev->second) +
                            "]");
        prescribed.emplace(key, i);
      }
      if (!any) r.fail(c, "expected at least one of x, y, z, found an empty map");
    } else if (given[0] == "pressure") {
      b.kind = BoundaryKind::pressure;
      b.pressure = r.expression(c);
    } else {
      b.kind = given[0] == "traction" ? BoundaryKind::traction : BoundaryKind::force;
      auto e = r.expression3(c);
      for (int k = 0; k < 3; ++k) b.components[k] = std::move(e[k]);
    }
    out.push_back(std::move(b));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Solver and output

/// Why the number of steps is bounded (max_steps).
const std::string too_many_steps =
    ": every step is a solve with a history row and a log line, so more steps only make the run "
    "and its outputs longer without resolving the load path better (split a long load history "
    "into several cases, or use larger steps)";

SolverSpec read_solver(const Reader& r, const std::optional<Val>& v, bool has_contact) {
  SolverSpec s;
  if (!v) return s;
  Map m(r, *v, solver_keys);
  if (auto x = m.get("scheme")) s.scheme = r.choice(*x, schemes, "scheme");
  if (auto x = m.get("curve_form")) s.curve_form = r.choice(*x, curve_forms, "curve form");
  if (auto x = m.get("times")) {
    for (const char* k : {"steps", "end"})
      if (m.has(k))
        throw InputError(
            r.at(m.key_mark(k), child_path(v->path, k)),
            std::string("give either 'times' or 'steps' and 'end', not both; found '") + k +
                "' with 'times'");
    if (!x->node.IsSequence())
      r.fail(*x, "expected a list of step end times [t1, t2, ...], found " + describe(x->node));
    if (x->node.size() > static_cast<std::size_t>(max_steps))
      r.fail(*x, "expected at most " + std::to_string(max_steps) + " step end times, found " +
                     std::to_string(x->node.size()) + too_many_steps);
    const auto items = r.list(*x, "a list of step end times [t1, t2, ...]");
    if (items.empty()) r.fail(*x, "expected at least one time, found an empty list");
    std::vector<double> times;
    for (const auto& it : items) {
      const double t = r.number(it);
      if (!(t > 0)) r.fail(it, "step end times must be > 0, found " + num(t));
      if (!times.empty() && !(t > times.back()))
        r.fail(it, "step end times must be strictly increasing, found " + num(t) + " after " +
                       num(times.back()));
      times.push_back(t);
    }
    s.times = StepTimes::list(std::move(times));
  } else {
    long steps = 1;
    if (auto x = m.get("steps")) {
      steps = r.integer(*x);
      if (steps < 1) r.fail(*x, "expected a whole number >= 1, found " + std::to_string(steps));
      if (steps > max_steps)
        r.fail(*x, "expected at most " + std::to_string(max_steps) + " steps, found " +
                       std::to_string(steps) + too_many_steps);
    }
    const double end = m.has("end") ? r.positive(*m.get("end")) : 1.0;
    s.times = StepTimes::equal(steps, end);
  }
  if (auto x = m.get("max_iterations")) s.max_iterations = r.integer_at_least(*x, 1);
  if (auto x = m.get("tolerance")) {
    s.tolerance = r.number(*x);
    if (!(s.tolerance > 0 && s.tolerance < 1))
      r.fail(*x, "expected a relative tolerance with 0 < tolerance < 1, found " + num(s.tolerance));
  }
  if (auto x = m.get("relaxation")) s.relaxation = r.positive(*x);
  if (auto x = m.get("correction")) {
    s.correction = r.number(*x);
    if (s.correction < 0)
      r.fail(*x, "expected a number >= 0 (0 turns the correction off), found " + num(s.correction));
  }
  if (auto x = m.get("cutback")) s.cutback = r.integer_at_least(*x, 0);
  if (auto x = m.get("mechanism_limit")) s.mechanism_limit = r.positive(*x);
  if (auto x = m.get("predictor"))
    s.extrapolate = r.choice(*x, predictors, "predictor") == "extrapolate";
  if (auto x = m.get("acceleration")) {
    s.anderson = r.choice(*x, accelerations, "acceleration") == "anderson";
    // Anderson mixing needs a fixed map u -> u + K^-1 r(u): a fixed matrix, and a point law that
    // depends on the iterate only (the initial-strain schemes carry their relaxed initial strain
    // from one iteration to the next).
    if (s.anderson && s.scheme != "initial-stress" && s.scheme != "initial-stress-stiffness")
      r.fail(*x,
             "acceleration: anderson applies to the schemes initial-stress and "
             "initial-stress-stiffness (a fixed matrix and a point law of the iterate alone), "
             "not to '" +
                 s.scheme + "'");
    // The contact's augmented forces are memory of the same kind (measured: Anderson needed
    // 155 iterations where the plain iteration needed 89 on a plastic indentation).
    if (s.anderson && has_contact)
      r.fail(*x,
             "acceleration: anderson cannot be combined with contact (the contact forces carry "
             "over from one iteration to the next, so the iteration is no fixed map of the "
             "displacements that Anderson mixing could accelerate); remove it");
  }
  if (auto x = m.get("linear")) {
    const std::string l = r.choice(*x, linear_solvers, "linear solver");
    s.linear = l == "direct"      ? SolverSpec::Linear::direct
               : l == "iterative" ? SolverSpec::Linear::iterative
                                  : SolverSpec::Linear::petsc;
  }
  if (auto x = m.get("petsc_options")) {
    s.petsc_options = r.string(*x);
    // Only options: a token that is no option must be the value of the one before it.
    std::istringstream in(s.petsc_options);
    std::string token, previous;
    while (in >> token) {
      const bool option = par::is_petsc_option_name(token);
      if (!option && (previous.empty() || previous[0] != '-'))
        r.fail(*x, "expected PETSc options such as \"-ksp_type cg -pc_type hypre\"; '" + token +
                       "' is neither an option (starting with '-') nor the value of one");
      previous = option ? token : std::string();
    }
  }
  return s;
}

bool valid_probe_name(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

// ---------------------------------------------------------------------------------------------
// Contact

/// A unit direction from a list of 3 numbers (not all zero).
Vec3 unit_vector(const Reader& r, const Val& v, const char* what) {
  const Vec3 d = r.vec3(v);
  if (!(d.norm() > 0)) r.fail(v, std::string("expected a non-zero ") + what + ", found [0, 0, 0]");
  return d.normalized();
}

std::vector<ContactSpec> read_contact(const Reader& r, const Val& v) {
  if (v.node.IsMap())
    r.fail(v, "expected a list of contacts (start each entry with '- '), found a map");
  std::vector<ContactSpec> out;
  std::map<std::string, std::size_t> names;
  const auto items = r.list(v, "a list of contacts");
  for (std::size_t i = 0; i < items.size(); ++i) {
    const Val& item = items[i];
    Map m(r, item, contact_keys,
          "a contact {name: ..., nodes: <region>, surface: {plane|sphere|cylinder|mesh: ...}}");
    ContactSpec c;
    c.where = r.at(item);
    c.name = "contact" + std::to_string(i);
    if (auto x = m.get("name")) {
      c.name = r.string(*x);
      if (!valid_probe_name(c.name))
        r.fail(*x,
               "contact names may use letters, digits, '_' and '-' only (they become column "
               "names), found '" +
                   c.name + "'");
    }
    if (auto prev = names.find(c.name); prev != names.end())
      r.fail(m.has("name") ? *m.get("name") : item, "contact name '" + c.name +
                                                        "' is already used by contact[" +
                                                        std::to_string(prev->second) + "]");
    names.emplace(c.name, i);
    const Val nodes = m.require(r, "nodes",
                                "the surface region of the body whose nodes may touch the rigid "
                                "surface");
    if (nodes.node.IsSequence())
      r.fail(nodes, "expected one region name, found a list; write one contact per region");
    c.nodes = r.string(nodes, "a region name");
    c.nodes_where = r.at(nodes);

    const Val surface =
        m.require(r, "surface", "the rigid surface: plane, sphere, cylinder or mesh");
    c.surface_where = r.at(surface);
    Map sm(r, surface, surface_kinds,
           "a surface {plane: ...}, {sphere: ...}, {cylinder: ...} or {mesh: {file: ...}}");
    std::vector<std::string> given;
    for (const auto& k : surface_kinds)
      if (sm.has(k)) given.push_back(k);
    if (given.empty())
      r.fail(surface, "expected one of 'plane', 'sphere', 'cylinder', 'mesh', found an empty map");
    if (given.size() > 1)
      throw InputError(r.at(sm.key_mark(given[1]), sm.get(given[1])->path),
                       "a contact has one surface, found both '" + given[0] + "' and '" + given[1] +
                           "'; write another contact entry");
    const Val g = *sm.get(given[0]);
    if (given[0] == "plane") {
      c.shape = ContactSpec::Shape::plane;
      Map pm(r, g, plane_keys, "a plane {point: [x, y, z], normal: [x, y, z]}");
      c.point = r.vec3(pm.require(r, "point", "a point of the plane"));
      c.normal = unit_vector(
          r, pm.require(r, "normal", "pointing from the rigid body towards the deformable one"),
          "normal");
    } else if (given[0] == "sphere") {
      c.shape = ContactSpec::Shape::sphere;
      Map pm(r, g, sphere_keys, "a sphere {center: [x, y, z], radius: r}");
      c.center = r.vec3(pm.require(r, "center", "the centre of the rigid ball"));
      c.radius = r.positive(pm.require(r, "radius", "the radius of the rigid ball"));
    } else if (given[0] == "cylinder") {
      c.shape = ContactSpec::Shape::cylinder;
      Map pm(r, g, cylinder_keys, "a cylinder {point: [x, y, z], axis: [x, y, z], radius: r}");
      c.point = r.vec3(pm.require(r, "point", "a point of the cylinder's axis"));
      c.axis = unit_vector(r, pm.require(r, "axis", "the direction of the axis"), "axis");
      c.radius = r.positive(pm.require(r, "radius", "the radius of the rigid cylinder"));
    } else {
      c.shape = ContactSpec::Shape::mesh;
      Map pm(r, g, stl_keys, "a mesh {file: body.stl, scale: 1}");
      const Val f = pm.require(r, "file", "a closed triangulated body in STL (ASCII or binary)");
      c.file = r.resolve(r.string(f, "a file name"));
      std::error_code ec;
      if (!fs::is_regular_file(c.file, ec))
        r.fail(f, "STL file '" + c.file.string() + "' not found");
      if (auto x = pm.get("scale")) c.scale = r.positive(*x);
    }
    if (auto x = m.get("motion")) {
      auto items3 = r.list3(*x, "numbers or expressions in t");
      for (int k = 0; k < 3; ++k) {
        Expression e = r.expression(items3[k]);
        if (e.depends_on_position())
          r.fail(items3[k], "the motion is a rigid translation: it may depend on t only, found '" +
                                e.text() + "'");
        c.motion[k] = std::move(e);
      }
    }
    if (auto x = m.get("stiffness")) {
      double k = 0;
      const bool is_auto = x->node.IsScalar() && trim(x->node.Scalar()) == "auto";
      if (!is_auto) {
        if (!x->node.IsScalar() || !parse_double(x->node.Scalar(), k) || !std::isfinite(k) ||
            !(k > 0))
          r.fail(*x,
                 "expected 'auto' or a penalty stiffness > 0 (force per length, per node), "
                 "found " +
                     describe(x->node));
        c.stiffness = k;
      }
    }
    if (auto x = m.get("penetration")) {
      c.penetration = r.positive(*x);
      if (c.penetration >= 1)
        r.fail(*x, "expected a fraction of the element size < 1, found " + num(c.penetration));
    }
    out.push_back(std::move(c));
  }
  return out;
}

OutputSpec read_output(const Reader& r, const std::optional<Val>& v, const fs::path& default_dir,
                       const std::vector<BoundarySpec>& boundary) {
  OutputSpec o;
  o.dir = default_dir;
  o.dir_where = SourceLocation{r.label(), 0, 0, "output.dir"};
  if (!v) return o;
  Map m(r, *v, output_keys);
  if (auto x = m.get("dir")) {
    o.dir = r.resolve(r.string(*x, "a folder name"));
    if (!o.dir.has_filename()) o.dir = o.dir.parent_path();  // "results/" is "results"
    o.dir_where = r.at(*x);
  }
  if (auto x = m.get("every")) o.every = r.integer_at_least(*x, 1);
  if (auto x = m.get("probes")) {
    if (x->node.IsMap())
      r.fail(*x, "expected a list of probes (start each entry with '- '), found a map");
    std::map<std::string, std::size_t> names;
    for (const auto& item : r.list(*x, "a list of probes")) {
      Map pm(r, item, probe_keys, "a probe {name: A, point: [x, y, z]}");
      ProbeSpec p;
      const Val name = pm.require(r, "name", "the probe's name, used in history.csv");
      p.name = r.string(name);
      if (!valid_probe_name(p.name))
        r.fail(name,
               "probe names may use letters, digits, '_' and '-' only (they become column "
               "names), found '" +
                   p.name + "'");
      if (auto prev = names.find(p.name); prev != names.end())
        r.fail(name, "probe name '" + p.name + "' is already used by output.probes[" +
                         std::to_string(prev->second) + "]");
      names.emplace(p.name, o.probes.size());
      const Val point = pm.require(r, "point", "the probe's coordinates [x, y, z]");
      p.point = r.vec3(point);
      p.where = r.at(point);
      o.probes.push_back(std::move(p));
    }
  }
  if (auto x = m.get("reactions")) {
    std::vector<std::string> fixed;  // regions with a displacement condition, in order
    for (const auto& b : boundary)
      if (b.kind == BoundaryKind::displacement &&
          std::find(fixed.begin(), fixed.end(), b.region) == fixed.end())
        fixed.push_back(b.region);
    for (const auto& item : r.names(*x)) {
      const std::string reg = r.string(item, "a region name");
      if (std::find(o.reactions.begin(), o.reactions.end(), reg) != o.reactions.end())
        r.fail(item, "region '" + reg + "' is listed twice");
      if (std::find(fixed.begin(), fixed.end(), reg) == fixed.end())
        r.fail(item, "region '" + reg +
                         "' has no displacement condition; reactions are "
                         "reported for regions with prescribed displacement. " +
                         suggestion(reg, fixed, "regions with a displacement condition"));
      o.reactions.push_back(reg);
      o.reaction_where.push_back(r.at(item));
    }
  }
  return o;
}

/// Tabs in the indentation are the most common cause of puzzling YAML syntax errors.
std::string tab_hint(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const auto indent = line.substr(0, line.find_first_not_of(" \t"));
    if (indent.find('\t') != std::string::npos)
      return " (line " + std::to_string(n) + " is indented with a tab; YAML needs spaces)";
  }
  return {};
}

}  // namespace

// ---------------------------------------------------------------------------------------------

Case read_case(const fs::path& case_file) {
  const std::string label = case_file.string();
  // fs::absolute throws on an empty path: say what a missing file says.
  if (case_file.empty())
    throw InputError(SourceLocation{}, "case file not found: the path is empty (\"\")");
  Case c;
  c.file = fs::absolute(case_file).lexically_normal();
  std::error_code ec;
  if (!fs::exists(c.file, ec))
    throw InputError(SourceLocation{label, 0, 0, ""}, "case file not found");
  if (!fs::is_regular_file(c.file, ec))
    throw InputError(SourceLocation{label, 0, 0, ""}, "expected a case file, found a directory");
  std::ifstream in(c.file, std::ios::binary);
  if (!in) throw InputError(SourceLocation{label, 0, 0, ""}, "cannot open the case file");
  std::ostringstream text;
  text << in.rdbuf();

  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::ParserException& e) {
    throw InputError(SourceLocation{label, e.mark.line >= 0 ? e.mark.line + 1 : 0,
                                    e.mark.column >= 0 ? e.mark.column + 1 : 0, ""},
                     "YAML syntax error: " + e.msg + tab_hint(text.str()));
  } catch (const YAML::Exception& e) {
    throw InputError(SourceLocation{label, e.mark.line >= 0 ? e.mark.line + 1 : 0,
                                    e.mark.column >= 0 ? e.mark.column + 1 : 0, ""},
                     "cannot read the YAML: " + e.msg);
  }

  const Reader r(label, c.file.parent_path());
  if (!root.IsDefined() || root.IsNull())
    throw InputError(SourceLocation{label, 0, 0, ""},
                     "the case file is empty: expected a map with at least the keys 'mesh' and "
                     "'materials'");
  YAML::Mark top_mark = root.Mark();
  if (top_mark.line < 0) top_mark = YAML::Mark();
  const Val top_val{root, "", top_mark};
  if (!root.IsMap())
    r.fail(top_val, "expected a map of keys (" + name_list(top_keys) +
                        ") at the top level, found " + describe(root));

  try {
    const Map top(r, top_val, top_keys);
    c.title = top.has("title") ? r.string(*top.get("title"), "a title") : c.file.stem().string();
    c.mesh = read_mesh(r, top.require(r, "mesh", "the mesh, e.g. mesh: {file: part.msh}"));
    c.materials =
        read_materials(r, top.require(r, "materials", "a list of materials with E, nu and alpha"),
                       top.has("temperature"));
    if (auto x = top.get("temperature")) {
      c.temperature = read_temperature(r, *x);
    } else {  // a table over temperature needs a temperature
      for (const auto& m : c.materials) {
        std::vector<const PropertyTable*> props = {&m.E, &m.nu, &m.alpha};
        if (m.plasticity) {
          const CurveSpec& curve = m.plasticity->curve;
          if (curve.kind == CurveSpec::Kind::table && curve.tables.size() > 1)
            throw InputError(curve.tables[1].where,
                             "curve tables at several temperatures need a 'temperature' "
                             "section (with its 'reference' and 'field')");
          if (curve.kind != CurveSpec::Kind::table) props.push_back(&curve.yield);
          if (curve.kind == CurveSpec::Kind::linear) props.push_back(&curve.hardening);
        }
        for (const PropertyTable* p : props)
          if (!p->is_constant())
            throw InputError(p->where,
                             "a table over temperature needs a 'temperature' section "
                             "(with its 'reference' and 'field')");
      }
    }
    if (auto x = top.get("boundary")) c.boundary = read_boundary(r, *x);
    if (auto x = top.get("body_force")) c.body_force = r.expression3(*x);
    if (auto x = top.get("contact")) c.contact = read_contact(r, *x);
    c.solver = read_solver(r, top.get("solver"), !c.contact.empty());
    c.output = read_output(r, top.get("output"),
                           c.file.parent_path() / (c.file.stem().string() + ".out"), c.boundary);
  } catch (const YAML::Exception& e) {  // not expected: all access is checked
    throw InputError(SourceLocation{label, e.mark.line >= 0 ? e.mark.line + 1 : 0,
                                    e.mark.column >= 0 ? e.mark.column + 1 : 0, ""},
                     "cannot read the YAML: " + e.msg);
  }
  return c;
}

}  // namespace hencky
