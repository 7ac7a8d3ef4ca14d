// The keywords of a deck that are not mesh data, read as the mesh reader meets them
// (input/inp_history.hpp). Their meaning is CalculiX's (User's Manual, ccx 2.20, section 7).
#include "input/inp_history.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace hencky::inp {

namespace {

/// The keywords the rest of the deck's meaning does not depend on.
bool is_harmless(const std::string& name) {
  return name == "PREPRINT" || name == "RESTART" || name == "NODE RESPONSE" || name == "MONITOR" ||
         name == "OUTPUT" || name == "CONTACT PRINT" || name == "CONTACT FILE" ||
         name == "SECTION PRINT" || name == "CONTACT OUTPUT";
}

}  // namespace

std::vector<std::vector<double>> DeckCase::numbers(const InpReader& r, int first, int end) const {
  std::vector<std::vector<double>> rows;
  for (int l = first; l < end; ++l) {
    std::vector<double> row;
    for (auto f : r.data(l)) row.push_back(r.real(f, l, "number"));
    rows.push_back(std::move(row));
  }
  return rows;
}

std::string DeckCase::place(const InpReader& r, int at) const {
  const Line& l = r.deck().lines[at];
  return fmt::format("{}:{}", std::filesystem::path(r.deck().names[l.file]).filename().string(),
                     l.number);
}

void DeckCase::refuse(const InpReader& r, int at, const std::string& why) {
  refusals_.push_back(place(r, at) + ": " + why);
  if (first_refusal_ < 0) first_refusal_ = at;
}

void DeckCase::note(const InpReader& r, int at, const std::string& what) {
  if (notes_.emplace(what, at).second) warnings_.push_back(place(r, at) + ": " + what);
}

void DeckCase::keyword(InpReader& r, const Keyword& k, int at, int first, int end) {
  const std::string& n = k.name;
  if (n == "HEADING") {
    if (first < end && spec_.title.empty())
      spec_.title = std::string(trim(r.deck().lines[first].text));
    return;
  }
  if (n == "MATERIAL" || n == "ELASTIC" || n == "PLASTIC" || n == "CYCLIC HARDENING" ||
      n == "EXPANSION" || n == "DENSITY" || n == "CONDUCTIVITY" || n == "SPECIFIC HEAT")
    return material_keyword(r, k, at, first, end);
  if (n == "SOLID SECTION") return section(r, k, at, first, end);
  if (n == "INITIAL CONDITIONS") return initial_conditions(r, k, at, first, end);
  if (n == "AMPLITUDE") return amplitude(r, k, at, first, end);
  if (n == "STEP") return step(r, k, at);
  if (n == "STATIC") return statik(r, k, at, first, end);
  if (n == "END STEP") {
    if (!in_step_) return refuse(r, at, "*END STEP without a *STEP");
    if (!step_has_procedure_)
      refuse(r, steps_.back().line,
             "*STEP without a procedure: hencky runs *STATIC, *HEAT TRANSFER and *COUPLED "
             "TEMPERATURE-DISPLACEMENT steps");
    in_step_ = false;
    return;
  }
  if (n == "BOUNDARY") return boundary(r, k, at, first, end);
  if (n == "CLOAD") return cload(r, k, at, first, end);
  if (n == "DLOAD") return dload(r, k, at, first, end);
  if (n == "TEMPERATURE") return temperature(r, k, at, first, end);
  if (n == "NODE PRINT" || n == "EL PRINT" || n == "NODE FILE" || n == "EL FILE" ||
      n == "NODE OUTPUT" || n == "ELEMENT OUTPUT")
    return output_request(r, k, at, first, end);
  if (n == "PHYSICAL CONSTANTS") return physical_constants(r, k, at);
  if (n == "HEAT TRANSFER" || n == "COUPLED TEMPERATURE-DISPLACEMENT" ||
      n == "UNCOUPLED TEMPERATURE-DISPLACEMENT")
    return heat_procedure(r, k, at, first, end);
  if (n == "FILM" || n == "RADIATE" || n == "DFLUX") return face_heat(r, k, at, first, end);
  if (n == "RESTART" && k.has("READ"))
    return refuse(r, at,
                  "*RESTART, READ: hencky continues a run with --restart DIR, not from "
                  "ccx's restart file");
  if (is_harmless(n)) return note(r, at, "*" + n + " has no meaning for hencky: left out");
  if (n == "CFLUX") return cflux(r, k, at, first, end);
  refuse(r, at, "*" + n + ": not a keyword hencky can honour");
}

// ---------------------------------------------------------------------------------------------
// Materials and sections

DeckCase::Material& DeckCase::current_material(const InpReader& r, const Keyword& k, int at) {
  if (material_ < 0) throw r.fail(at, "*" + k.name + " outside a *MATERIAL");
  return materials_[static_cast<std::size_t>(material_)];
}

void DeckCase::material_keyword(InpReader& r, const Keyword& k, int at, int first, int end) {
  if (k.name == "MATERIAL") {
    const std::string* name = k.get("NAME");
    if (!name || name->empty()) throw r.fail(at, "*MATERIAL needs NAME=<name>");
    for (const Material& m : materials_)
      if (upper(m.spec.name) == upper(*name))
        throw r.fail(at, fmt::format("material '{}' is defined twice (first on line {})", *name,
                                     r.deck().lines[m.line].number));
    Material m;
    m.spec.name = unquote(*name);
    m.line = at;
    m.spec.where = r.where(at);
    materials_.push_back(std::move(m));
    material_ = static_cast<int>(materials_.size()) - 1;
    return;
  }
  if (k.name == "ELASTIC") return elastic(r, k, at, first, end);
  if (k.name == "PLASTIC") return plastic(r, k, at, first, end);
  if (k.name == "CYCLIC HARDENING") return cyclic_hardening(r, k, at, first, end);
  Material& m = current_material(r, k, at);
  // EXPANSION, DENSITY, CONDUCTIVITY, SPECIFIC HEAT: a value and its temperature per line.
  PropertyTable& p = k.name == "EXPANSION"      ? m.spec.alpha
                     : k.name == "DENSITY"      ? m.spec.density
                     : k.name == "CONDUCTIVITY" ? m.spec.conductivity
                                                : m.spec.specific_heat;
  if (k.name == "EXPANSION") {
    if (const std::string* type = k.get("TYPE"); type && upper(*type) != "ISO")
      return refuse(r, at, "*EXPANSION, TYPE=" + *type + ": hencky's materials are isotropic");
    if (const std::string* zero = k.get("ZERO")) m.expansion_zero = r.real(*zero, at, "ZERO");
  }
  if (k.name == "CONDUCTIVITY")
    if (const std::string* type = k.get("TYPE"); type && upper(*type) != "ISO")
      return refuse(r, at, "*CONDUCTIVITY, TYPE=" + *type + ": hencky's materials are isotropic");
  p.where = r.where(at);
  for (const auto& row : numbers(r, first, end)) {
    if (row.empty()) continue;
    p.value.push_back(row[0]);
    if (row.size() > 1) p.temperature.push_back(row[1]);
  }
  if (p.value.empty()) throw r.fail(at, "*" + k.name + " without a value");
  if (p.value.size() == 1) {
    p.temperature.clear();
  } else if (p.temperature.size() != p.value.size() ||
             std::adjacent_find(p.temperature.begin(), p.temperature.end(), [](double a, double b) {
               return !(b > a);
             }) != p.temperature.end()) {
    throw r.fail(at, "*" + k.name +
                         ": a table over temperature has a value and a temperature on each "
                         "line, the temperatures increasing");
  }
}

void DeckCase::elastic(InpReader& r, const Keyword& k, int at, int first, int end) {
  Material& m = current_material(r, k, at);
  if (const std::string* type = k.get("TYPE"); type && upper(*type) != "ISO")
    return refuse(r, at, "*ELASTIC, TYPE=" + *type + ": hencky's materials are isotropic");
  m.spec.E = {};
  m.spec.nu = {};
  m.spec.E.where = m.spec.nu.where = r.where(at);
  const auto rows = numbers(r, first, end);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    const int l = first + static_cast<int>(i);
    if (row.size() < 2) throw r.fail(l, "an *ELASTIC line is 'E, nu' or 'E, nu, temperature'");
    if (!(row[0] > 0)) throw r.fail(l, fmt::format("E must be > 0, found {:g}", row[0]));
    if (!(row[1] > -1 && row[1] < 0.5))
      throw r.fail(l, fmt::format("nu must lie in (-1, 0.5), found {:g}", row[1]));
    m.spec.E.value.push_back(row[0]);
    m.spec.nu.value.push_back(row[1]);
    if (row.size() > 2) {
      if (!m.spec.E.temperature.empty() && !(row[2] > m.spec.E.temperature.back()))
        throw r.fail(l, "*ELASTIC: the temperatures of the table must increase");
      m.spec.E.temperature.push_back(row[2]);
    }
  }
  if (rows.empty()) throw r.fail(at, "*ELASTIC without a line of E and nu");
  if (rows.size() == 1) {
    m.spec.E.temperature.clear();
  } else if (m.spec.E.temperature.size() != rows.size()) {
    throw r.fail(at, "*ELASTIC: a table of several lines needs a temperature on each");
  }
  m.spec.nu.temperature = m.spec.E.temperature;
}

CurveSpec DeckCase::plastic_curve(InpReader& r, const Keyword& k, int at, int first, int end) {
  const std::string what = "*" + k.name;
  CurveSpec curve;
  curve.where = r.where(at);
  curve.kind = CurveSpec::Kind::table;
  curve.form = CurveSpec::Form::plastic;
  const auto rows = numbers(r, first, end);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    const int l = first + static_cast<int>(i);
    if (row.size() < 2)
      throw r.fail(l, "a " + what +
                          " line is 'stress, plastic strain' or 'stress, plastic strain, "
                          "temperature'");
    const double T = row.size() > 2 ? row[2] : 0;
    auto& tables = curve.tables;
    if (tables.empty() || tables.back().temperature != T) {
      if (!tables.empty() && !(T > tables.back().temperature))
        throw r.fail(l, what + ": the temperatures of the curves must increase");
      CurveSpec::Table t;
      t.temperature = T;
      t.where = r.where(l);
      tables.push_back(std::move(t));
    }
    auto& t = tables.back();
    if (t.strain.empty() && row[1] != 0)
      throw r.fail(l, fmt::format("{}: each curve starts at plastic strain 0 (the yield "
                                  "stress), found {:g}",
                                  what, row[1]));
    if (!t.strain.empty() && !(row[1] > t.strain.back()))
      throw r.fail(l, what + ": the plastic strains of a curve must increase");
    if (!(row[0] > 0))
      throw r.fail(l, fmt::format("{}: a stress must be > 0, found {:g}", what, row[0]));
    t.strain.push_back(row[1]);
    t.stress.push_back(row[0]);
    t.point_where.push_back(r.where(l));
  }
  if (rows.empty()) throw r.fail(at, what + " without a line of stress and plastic strain");
  return curve;
}

void DeckCase::plastic(InpReader& r, const Keyword& k, int at, int first, int end) {
  Material& m = current_material(r, k, at);
  const std::string* h = k.get("HARDENING");
  const std::string hardening = h ? upper(*h) : "ISOTROPIC";
  const bool kinematic = hardening == "KINEMATIC" || hardening == "COMBINED";
  if (hardening != "ISOTROPIC" && !kinematic)
    return refuse(r, at,
                  "*PLASTIC, HARDENING=" + *h +
                      ": hencky reads isotropic, linear kinematic and combined hardening from a "
                      "deck (Armstrong-Frederick back stresses are plasticity.kinematic of "
                      "case.yaml)");
  for (const auto& [name, v] : k.params)
    if (name != "HARDENING" && name != "DATATYPE" && name != "NUMBER BACKSTRESSES")
      return refuse(
          r, at, fmt::format("*PLASTIC, {}{}: not read by hencky", name, v.empty() ? "" : "=" + v));
  if (const std::string* d = k.get("DATATYPE"); d && upper(*d) != "PARAMETERS")
    return refuse(r, at, "*PLASTIC, DATATYPE=" + *d + ": hencky reads PARAMETERS (or a table)");
  if (const std::string* d = k.get("DATATYPE"); d && upper(*d) == "PARAMETERS") {
    if (hardening != "COMBINED")
      return refuse(r, at,
                    "*PLASTIC, DATATYPE=PARAMETERS: hencky reads it with HARDENING=COMBINED");
    return back_stress_parameters(r, k, at, first, end, m);
  }
  PlasticitySpec p;
  p.where = r.where(at);
  p.curve = plastic_curve(r, k, at, first, end);
  if (kinematic) {
    // ccx's linear kinematic hardening: the yield stress and one more point, whose slope is
    // Prager's modulus (the uniaxial dσ/dε^p of the moving surface, hencky's C).
    const auto& tables = p.curve.tables;
    if (tables.size() != 1 || tables[0].strain.size() != 2)
      return refuse(r, at,
                    "*PLASTIC, HARDENING=" + hardening +
                        ": hencky reads two lines at one temperature (the yield stress at plastic "
                        "strain 0 and one more point: linear kinematic hardening)");
    const CurveSpec::Table& t = tables[0];
    PlasticitySpec kp;
    kp.where = kp.curve.where = kp.law.where = r.where(at);
    kp.curve.kind = CurveSpec::Kind::perfect;
    kp.curve.yield.value = {t.stress[0]};
    kp.curve.yield.where = r.where(at);
    PropertyTable c, gamma;
    c.value = {(t.stress[1] - t.stress[0]) / t.strain[1]};
    gamma.value = {0.0};
    c.where = gamma.where = r.where(at);
    if (!(c.value[0] >= 0))
      return refuse(r, at,
                    "*PLASTIC, HARDENING=" + hardening +
                        ": the stress falls (a softening back stress); hencky's kinematic "
                        "modulus is >= 0");
    kp.law.law = "kinematic";
    kp.law.keys["kinematic"] = {LawParameters::Group{{"C", c}, {"gamma", gamma}}};
    m.spec.plasticity = std::move(kp);
    // COMBINED: the isotropic part is *CYCLIC HARDENING's curve, which follows.
    m.combined_line = hardening == "COMBINED" ? at : -1;
    return;
  }
  m.spec.plasticity = std::move(p);
  m.combined_line = -1;
}

void DeckCase::back_stress_parameters(InpReader& r, const Keyword& k, int at, int first, int end,
                                      Material& m) {
  // Abaqus's `σ|0, C1, γ1, C2, γ2, ..., [T]` per line (one line per temperature): the
  // isotropic part stays at σ|0 without *CYCLIC HARDENING, as there.
  int n = 1;
  if (const std::string* b = k.get("NUMBER BACKSTRESSES")) {
    const double v = r.real(*b, at, "NUMBER BACKSTRESSES");
    if (!(v >= 1 && v <= 3 && v == std::floor(v)))
      return refuse(r, at,
                    fmt::format("*PLASTIC, NUMBER BACKSTRESSES={}: hencky reads 1 to 3 (a line "
                                "each temperature)",
                                *b));
    n = static_cast<int>(v);
  }
  PlasticitySpec kp;
  kp.where = kp.curve.where = kp.law.where = r.where(at);
  kp.curve.kind = CurveSpec::Kind::perfect;
  kp.curve.yield.where = r.where(at);
  std::vector<PropertyTable> c(static_cast<std::size_t>(n)), gamma(c.size());
  const auto rows = numbers(r, first, end);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    const int l = first + static_cast<int>(i);
    const std::size_t need = 1 + 2 * static_cast<std::size_t>(n);
    if (row.size() != need && row.size() != need + 1)
      throw r.fail(l, fmt::format("a *PLASTIC, DATATYPE=PARAMETERS line is 'yield stress, C1, "
                                  "gamma1, ...' for {} back stress{}, then the temperature",
                                  n, n > 1 ? "es" : ""));
    auto add = [&](PropertyTable& t, double v) {
      t.value.push_back(v);
      if (row.size() > need) t.temperature.push_back(row[need]);
      t.where = r.where(l);
    };
    if (!(row[0] > 0))
      throw r.fail(l, fmt::format("the yield stress must be > 0, found {:g}", row[0]));
    add(kp.curve.yield, row[0]);
    for (std::size_t j = 0; j < c.size(); ++j) {
      if (!(row[1 + 2 * j] >= 0 && row[2 + 2 * j] >= 0))
        throw r.fail(l, "C and gamma must be >= 0");
      add(c[j], row[1 + 2 * j]);
      add(gamma[j], row[2 + 2 * j]);
    }
  }
  if (rows.empty()) throw r.fail(at, "*PLASTIC, DATATYPE=PARAMETERS without a line");
  const auto& temps = kp.curve.yield.temperature;
  if (rows.size() > 1 && (temps.size() != rows.size() ||
                          std::adjacent_find(temps.begin(), temps.end(), [](double a, double b) {
                            return !(b > a);
                          }) != temps.end()))
    throw r.fail(at, "*PLASTIC, DATATYPE=PARAMETERS: several lines need increasing temperatures");
  if (rows.size() == 1) {
    kp.curve.yield.temperature.clear();
    for (std::size_t j = 0; j < c.size(); ++j)
      c[j].temperature.clear(), gamma[j].temperature.clear();
  }
  kp.law.law = "kinematic";
  for (std::size_t j = 0; j < c.size(); ++j)
    kp.law.keys["kinematic"].push_back(LawParameters::Group{{"C", c[j]}, {"gamma", gamma[j]}});
  m.spec.plasticity = std::move(kp);
  m.combined_line = -1;
}

void DeckCase::cyclic_hardening(InpReader& r, const Keyword& k, int at, int first, int end) {
  Material& m = current_material(r, k, at);
  if (k.has("PARAMETERS"))
    return refuse(r, at,
                  "*CYCLIC HARDENING, PARAMETERS: hencky's isotropic part is a curve (give it as "
                  "a table of stress and plastic strain)");
  if (m.combined_line < 0 || !m.spec.plasticity)
    return refuse(r, at, "*CYCLIC HARDENING without a *PLASTIC, HARDENING=COMBINED before it");
  m.spec.plasticity->curve = plastic_curve(r, k, at, first, end);
  m.cyclic = true;
}

void DeckCase::section(InpReader& r, const Keyword& k, int at, int first, int end) {
  (void)first;
  (void)end;
  const std::string* elset = k.get("ELSET");
  const std::string* material = k.get("MATERIAL");
  if (!elset || !material) throw r.fail(at, "*SOLID SECTION needs ELSET= and MATERIAL=");
  if (k.has("ORIENTATION"))
    note(r, at,
         "*SOLID SECTION, ORIENTATION=: left out (the materials hencky reads are isotropic)");
  r.element_targets(*elset, at);  // it must be an ELSET
  sections_.push_back({unquote(*elset), unquote(*material), at});
}

void DeckCase::bind_sections(InpReader& r) {
  for (const Section& sec : sections_) {
    const auto it = std::find_if(materials_.begin(), materials_.end(), [&](const Material& m) {
      return upper(m.spec.name) == upper(sec.material);
    });
    if (it == materials_.end())
      throw r.fail(sec.line, fmt::format("*SOLID SECTION: the deck has no *MATERIAL named '{}'",
                                         sec.material));
    it->used = true;
    it->spec.regions.push_back(sec.elset);
    it->spec.region_where.push_back(r.where(sec.line));
  }
}

void DeckCase::initial_conditions(InpReader& r, const Keyword& k, int at, int first, int end) {
  const std::string* type = k.get("TYPE");
  if (!type || upper(*type) != "TEMPERATURE")
    return refuse(r, at,
                  "*INITIAL CONDITIONS, TYPE=" + (type ? *type : std::string("(none)")) +
                      ": hencky starts from an unstressed body at rest; it reads "
                      "TYPE=TEMPERATURE");
  initial_line_ = at;
  for (int l = first; l < end; ++l) {
    const auto f = r.data(l);
    if (f.size() < 2) throw r.fail(l, "an initial temperature line is 'node or NSET, value'");
    const double T = r.real(f[1], l, "temperature");
    for (long n : r.node_targets(f[0], l)) initial_temperature_[n] = T;
  }
}

void DeckCase::amplitude(InpReader& r, const Keyword& k, int at, int first, int end) {
  const std::string* name = k.get("NAME");
  if (!name || name->empty()) throw r.fail(at, "*AMPLITUDE needs NAME=<name>");
  for (const char* p : {"SHIFTX", "SHIFTY", "USER"})
    if (k.has(p)) return refuse(r, at, fmt::format("*AMPLITUDE, {}: not read by hencky", p));
  if (const std::string* d = k.get("DEFINITION"); d && upper(*d) != "TABULAR")
    return refuse(r, at, "*AMPLITUDE, DEFINITION=" + *d + ": hencky reads TABULAR");
  Amplitude a;
  if (const std::string* time = k.get("TIME")) {
    const std::string t = upper(*time);
    if (t != "TOTAL TIME" && t != "STEP TIME")
      throw r.fail(at, "*AMPLITUDE, TIME= is STEP TIME or TOTAL TIME, found '" + *time + "'");
    a.total_time = t == "TOTAL TIME";
  }
  for (int l = first; l < end; ++l) {
    const auto f = r.data(l);
    if (f.size() % 2 != 0) throw r.fail(l, "an *AMPLITUDE line holds pairs of time and value");
    for (std::size_t i = 0; i < f.size(); i += 2) {
      const double t = r.real(f[i], l, "time");
      auto& times = a.factor.temperature;
      if (!times.empty() && !(t > times.back()))
        throw r.fail(l, "*AMPLITUDE: the times must increase");
      times.push_back(t);
      a.factor.value.push_back(r.real(f[i + 1], l, "value"));
    }
  }
  if (!a.defined()) throw r.fail(at, "*AMPLITUDE without a pair of time and value");
  a.factor.where = r.where(at);
  const auto [it, fresh] =
      amplitude_of_.try_emplace(upper(unquote(*name)), static_cast<int>(amplitudes_.size()));
  if (fresh) {
    a.name = unquote(*name);
    amplitudes_.push_back(std::move(a));
    return;
  }
  Amplitude& named = amplitudes_[static_cast<std::size_t>(it->second)];
  if (named.defined()) throw r.fail(at, fmt::format("amplitude '{}' is defined twice", *name));
  // Named by a condition before it is defined, as ccx allows; not by one of a step that has
  // ended (its values at that step's end are already taken).
  if (named.used_step < step_index() && named.used_step >= 0)
    return refuse(r, at,
                  fmt::format("*AMPLITUDE '{}' is defined after step {}, which uses it: define "
                              "it before",
                              *name, named.used_step + 1));
  a.name = named.name;
  a.used_line = named.used_line;
  a.used_step = named.used_step;
  named = std::move(a);
}

// ---------------------------------------------------------------------------------------------
// Steps

void DeckCase::step(InpReader& r, const Keyword& k, int at) {
  if (in_step_) throw r.fail(at, "*STEP inside a step (the last one has no *END STEP)");
  for (const auto& [p, v] : k.params) {
    if (p == "NLGEOM" || p == "INC" || p == "NAME") continue;
    if (p == "AMPLITUDE" && upper(v) == "RAMP") continue;
    refuse(r, at, fmt::format("*STEP, {}{}: not read by hencky", p, v.empty() ? "" : "=" + v));
  }
  DeckStep s;
  s.line = at;
  const std::string* nl = k.get("NLGEOM");
  s.nlgeom = nl && upper(*nl) != "NO";
  if (!steps_.empty()) {
    s.start = steps_.back().end;
    // ccx: once on, NLGEOM stays on in the steps after.
    s.nlgeom = s.nlgeom || steps_.back().nlgeom;
  }
  s.end = s.start + 1;
  steps_.push_back(s);
  in_step_ = true;
  step_has_procedure_ = false;
}

void DeckCase::statik(InpReader& r, const Keyword& k, int at, int first, int end) {
  if (!in_step_) throw r.fail(at, "*STATIC outside a *STEP");
  if (step_has_procedure_) return refuse(r, at, "a second procedure in one *STEP");
  step_has_procedure_ = true;
  DeckStep& s = steps_.back();
  s.procedure = DeckStep::Procedure::statik;
  s.direct = k.has("DIRECT");
  for (const auto& [p, v] : k.params) {
    if (p == "DIRECT" || p == "SOLVER") continue;
    refuse(r, at, fmt::format("*STATIC, {}{}: not read by hencky", p, v.empty() ? "" : "=" + v));
  }
  double dt0 = 1, period = 1;
  if (first < end) {
    const auto f = r.data(first);
    if (f.size() > 0) dt0 = r.real(f[0], first, "initial increment");
    if (f.size() > 1) period = r.real(f[1], first, "time period");
  }
  if (!(period > 0))
    throw r.fail(first, fmt::format("the step's time period must be > 0, found {:g}", period));
  if (!(dt0 > 0) || dt0 > period) dt0 = period;
  s.end = s.start + period;
  s.increment = dt0;
}

// ---------------------------------------------------------------------------------------------
// Conditions

Course::InStep& DeckCase::in_step(Course& c) {
  const std::size_t s = static_cast<std::size_t>(std::max(step_index(), 0));
  while (c.step.size() <= s) {
    Course::InStep next;
    if (!c.step.empty() && c.step.back().set) {  // carried: held at its value at the step's end
      next.set = true;
      next.value = value_at_end(c, static_cast<int>(c.step.size()) - 1);
      next.line = c.step.back().line;
    }
    c.step.push_back(next);
  }
  return c.step[s];
}

int DeckCase::condition_options(InpReader& r, const Keyword& k, int at, bool& op_new,
                                const std::vector<std::string>& allowed) {
  int amp = -1;
  op_new = false;
  for (const auto& [p, v] : k.params) {
    if (p == "OP") {
      const std::string op = upper(v);
      if (op != "NEW" && op != "MOD") throw r.fail(at, "OP= is NEW or MOD, found '" + v + "'");
      op_new = op == "NEW";
    } else if (p == "AMPLITUDE") {
      const auto [it, fresh] =
          amplitude_of_.try_emplace(upper(unquote(v)), static_cast<int>(amplitudes_.size()));
      if (fresh) {  // defined later in the deck (checked at its end)
        Amplitude named;
        named.name = unquote(v);
        named.used_line = at;
        amplitudes_.push_back(std::move(named));
      }
      amp = it->second;
      amplitudes_[static_cast<std::size_t>(amp)].used_step = step_index();
    } else if (std::find(allowed.begin(), allowed.end(), p) == allowed.end()) {
      refuse(r, at,
             fmt::format("*{}, {}{}: not read by hencky", k.name, p, v.empty() ? "" : "=" + v));
    }
  }
  if (!in_step_ && (op_new || amp >= 0))
    refuse(r, at, "*" + k.name + " of the model data with OP= or AMPLITUDE=: give them in a step");
  return amp;
}

void DeckCase::boundary(InpReader& r, const Keyword& k, int at, int first, int end) {
  bool op_new = false;
  const int amp = condition_options(r, k, at, op_new, {"TYPE"});
  if (const std::string* type = k.get("TYPE"); type && upper(*type) != "DISPLACEMENT")
    return refuse(r, at, "*BOUNDARY, TYPE=" + *type + ": hencky prescribes displacements");
  if (op_new) {
    remove_unnamed(displacement_, at, false);
    remove_unnamed(fixed_temperature_, at, false);
  }
  for (int l = first; l < end; ++l) {
    const auto f = r.data_in_place(l);
    if (f.size() < 2 || f[0].empty() || f[1].empty())
      throw r.fail(l, "a *BOUNDARY line is 'node or NSET, first dof[, last dof[, value]]'");
    const long d1 = r.label(f[1], l, "degree of freedom");
    const long d2 = f.size() > 2 && !f[2].empty() ? r.label(f[2], l, "degree of freedom") : d1;
    const double value = f.size() > 3 && !f[3].empty() ? r.real(f[3], l, "displacement") : 0.0;
    if (d2 < d1)
      throw r.fail(l, fmt::format("the last degree of freedom {} is below the first {}", d2, d1));
    if (d1 == 11 && d2 == 11) {  // a temperature (heat transfer and coupled steps)
      const double T = f.size() > 3 && !f[3].empty() ? r.real(f[3], l, "temperature") : 0.0;
      for (long n : r.node_targets(f[0], l))
        in_step(fixed_temperature_[n]) = {true, true, T, amp, l};
      continue;
    }
    if (d1 > 3 || d2 > 3) {
      refuse(r, l,
             fmt::format("*BOUNDARY on degree of freedom {}: hencky's solid elements have the "
                         "displacements 1 .. 3 alone",
                         d2 > 3 ? d2 : d1));
      continue;
    }
    for (long n : r.node_targets(f[0], l))
      for (long d = d1; d <= d2; ++d) {
        in_step(displacement_[{n, static_cast<int>(d - 1)}]) = {true, true, value, amp, l};
      }
  }
}

void DeckCase::cload(InpReader& r, const Keyword& k, int at, int first, int end) {
  bool op_new = false;
  const int amp = condition_options(r, k, at, op_new, {});
  if (op_new) remove_unnamed(cload_, at, true);
  for (int l = first; l < end; ++l) {
    const auto f = r.data(l);
    if (f.size() < 3) throw r.fail(l, "a *CLOAD line is 'node or NSET, dof, value'");
    const long d = r.label(f[1], l, "degree of freedom");
    const double value = r.real(f[2], l, "force");
    if (d > 3) {
      refuse(r, l,
             fmt::format("*CLOAD on degree of freedom {}: hencky's solid elements have "
                         "the forces 1 .. 3 alone",
                         d));
      continue;
    }
    for (long n : r.node_targets(f[0], l))
      in_step(cload_[{n, static_cast<int>(d - 1)}]) = {true, true, value, amp, l};
  }
}

void DeckCase::dload(InpReader& r, const Keyword& k, int at, int first, int end) {
  bool op_new = false;
  const int amp = condition_options(r, k, at, op_new, {});
  if (op_new) remove_unnamed(pressure_, at, true);
  for (int l = first; l < end; ++l) {
    const auto f = r.data(l);
    if (f.size() < 3)
      throw r.fail(l, "a *DLOAD line is 'element, ELSET or surface, type, magnitude'");
    const std::string type = upper(f[1]);
    const double value = r.real(f[2], l, "magnitude");
    if (type == "GRAV") {
      if (f.size() < 6) throw r.fail(l, "a GRAV line is 'ELSET, GRAV, g, nx, ny, nz'");
      Gravity g;
      std::array<double, 3> n{};
      for (int d = 0; d < 3; ++d) n[d] = r.real(f[3 + d], l, "direction");
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      if (!(len > 0)) throw r.fail(l, "GRAV: the direction (nx, ny, nz) is zero");
      for (int d = 0; d < 3; ++d) g.g[d] = value * n[d] / len;
      g.line = l;
      g.step = std::max(step_index(), 0);
      if (amp >= 0) refuse(r, at, "*DLOAD GRAV with an AMPLITUDE: not read by hencky");
      gravity_.push_back(g);
      if (!r.covers_body(r.element_targets(f[0], l)))
        refuse(r, l, "GRAV on a part of the body: hencky's body force acts on all of it");
      continue;
    }
    int side = 0;
    if (type.size() == 2 && type[0] == 'P' && type[1] >= '1' && type[1] <= '6')
      side = type[1] - '0';
    else if (type == "P" && InpReader::is_label(f[0])) {
      refuse(r, l,
             "*DLOAD P on element " + std::string(f[0]) +
                 ": a pressure without its face is a shell's, and hencky's elements are solids "
                 "(name the face, P1 .. P6, or a *SURFACE)");
      continue;
    } else if (type != "P") {
      refuse(r, l, "*DLOAD of type " + type + ": hencky reads P, P1 .. P6 and GRAV");
      continue;
    }
    for (const ElementFace& face : r.face_targets(f[0], side, l))
      in_step(pressure_[face]) = {true, true, value, amp, l};
  }
}

void DeckCase::temperature(InpReader& r, const Keyword& k, int at, int first, int end) {
  bool op_new = false;
  const int amp = condition_options(r, k, at, op_new, {"BSWITCH"});
  if (!in_step_) throw r.fail(at, "*TEMPERATURE outside a *STEP");
  if (amp >= 0) refuse(r, at, "*TEMPERATURE with an AMPLITUDE: not read by hencky yet");
  if (op_new) remove_unnamed(temperature_, at, false);
  for (int l = first; l < end; ++l) {
    const auto f = r.data(l);
    if (f.size() < 2) throw r.fail(l, "a *TEMPERATURE line is 'node or NSET, temperature'");
    const double T = r.real(f[1], l, "temperature");
    for (long n : r.node_targets(f[0], l)) in_step(temperature_[n]) = {true, true, T, -1, l};
  }
}

}  // namespace hencky::inp
