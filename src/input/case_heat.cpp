// The heat section: heat conduction on the same mesh (analysis, initial temperature, θ, source,
// boundary conditions, steps, Newton settings, radiation constants), and the rules it makes
// for the materials and the temperature section.
#include <algorithm>
#include <cmath>

#include "input/case_sections.hpp"

namespace hencky {

const char* to_string(HeatBoundarySpec::Kind kind) {
  switch (kind) {
    case HeatBoundarySpec::Kind::temperature:
      return "temperature";
    case HeatBoundarySpec::Kind::flux:
      return "flux";
    case HeatBoundarySpec::Kind::convection:
      return "convection";
    case HeatBoundarySpec::Kind::radiation:
      return "radiation";
    case HeatBoundarySpec::Kind::nodal_flux:
      return "nodal_flux";
  }
  return "?";
}

namespace case_input {

namespace {

// clang-format off
const std::vector<std::string> heat_keys = {
    "analysis",  "initial",        "theta",         "source",          "boundary",
    "steps",     "times",          "tolerance",     "max_iterations",  "absolute_zero",
    "stefan_boltzmann"};
// clang-format on
const std::vector<std::string> heat_boundary_keys = {"region",     "temperature", "flux",
                                                     "convection", "radiation",   "nodal_flux"};
const std::vector<std::string> heat_conditions = {"temperature", "flux", "convection", "radiation",
                                                  "nodal_flux"};
const std::vector<std::string> convection_keys = {"h", "ambient"};
const std::vector<std::string> radiation_keys = {"emissivity", "ambient"};
const std::vector<std::string> analyses = {"steady", "transient"};

const KeySection heat_key_sections[] = {
    {"heat", &heat_keys},
    {"heat.boundary[i]", &heat_boundary_keys},
    {"heat.boundary[i].convection", &convection_keys},
    {"heat.boundary[i].radiation", &radiation_keys},
};

/// A constant value below `lo` (or above `hi`) is refused now; an expression is checked where
/// it is evaluated (face_flux, solve/heat_terms.cpp).
void check_constant_range(const Reader& r, const Val& v, const Expression& e, double lo, double hi,
                          const std::string& what) {
  if (!e.is_constant()) return;
  const double x = e(0, 0, 0, 0);
  if (x < lo || x > hi)
    r.fail(v, what + " must be " +
                  (std::isinf(hi) ? ">= " + num(lo) : "in " + num(lo) + " .. " + num(hi)) +
                  ", found " + num(x));
}

HeatBoundarySpec read_heat_condition(const Reader& r, const Val& item) {
  Map m(r, item, heat_boundary_keys,
        "a condition {region: ..., temperature|flux|convection|radiation|nodal_flux: ...}");
  HeatBoundarySpec b;
  const Val region = m.require(r, "region", "the Gmsh physical group the condition acts on");
  if (region.node.IsSequence())
    r.fail(region, "expected one region name, found a list; write one entry per region");
  b.region = r.string(region, "a region name");
  b.where = r.at(region);
  std::vector<std::string> given;
  for (const auto& c : heat_conditions)
    if (m.has(c)) given.push_back(c);
  if (given.empty())
    r.fail(item, "heat boundary entry for region '" + b.region +
                     "' has no condition: expected one of 'temperature', 'flux', 'convection', "
                     "'radiation', 'nodal_flux'");
  if (given.size() > 1)
    throw InputError(r.at(m.key_mark(given[1]), child_path(item.path, given[1])),
                     "a heat boundary entry has one condition, found both '" + given[0] +
                         "' and '" + given[1] + "'; write another entry for the same region");
  const Val c = *m.get(given[0]);
  b.value_where = r.at(c);
  if (given[0] == "temperature" || given[0] == "flux" || given[0] == "nodal_flux") {
    b.kind = given[0] == "temperature" ? HeatBoundarySpec::Kind::temperature
             : given[0] == "flux"      ? HeatBoundarySpec::Kind::flux
                                       : HeatBoundarySpec::Kind::nodal_flux;
    b.value = r.expression(c);
    return b;
  }
  const bool convection = given[0] == "convection";
  b.kind = convection ? HeatBoundarySpec::Kind::convection : HeatBoundarySpec::Kind::radiation;
  Map cm(r, c, convection ? convection_keys : radiation_keys,
         convection ? "a map {h: ..., ambient: ...}" : "a map {emissivity: ..., ambient: ...}");
  const char* coefficient = convection ? "h" : "emissivity";
  const Val k = cm.require(r, coefficient,
                           convection ? "the film coefficient h in W/(m^2 K), e.g. h: 25"
                                      : "the surface emissivity (0 .. 1), e.g. emissivity: 0.8");
  b.value = r.expression(k);
  b.value_where = r.at(k);
  if (convection)
    check_constant_range(r, k, b.value, 0, INFINITY, "the film coefficient h");
  else
    check_constant_range(r, k, b.value, 0, 1, "the emissivity");
  b.ambient = r.expression(cm.require(r, "ambient", "the ambient temperature, e.g. 20"));
  return b;
}

}  // namespace

std::span<const KeySection> heat_sections() {
  return heat_key_sections;
}

HeatSpec read_heat(const Reader& r, const Val& v, const StepTimes& mechanical) {
  Map m(r, v, heat_keys, "a map {analysis: ..., boundary: [...], ...}");
  HeatSpec h;
  h.given = true;
  h.where = r.at(v);
  if (auto x = m.get("analysis")) h.transient = r.choice(*x, analyses, "analysis") == "transient";
  if (auto x = m.get("initial")) {
    h.initial = r.expression(*x);
    if (h.initial->depends_on_time())
      r.fail(*x, "the initial temperature is an expression of x, y, z only, found t in \"" +
                     h.initial->text() + "\"");
  }
  if (auto x = m.get("theta")) {
    h.theta = r.number(*x);
    if (!(h.theta >= 0.5 && h.theta <= 1.0))
      r.fail(*x,
             "theta must be in 0.5 .. 1 (1 backward Euler, 0.5 Crank-Nicolson; below 0.5 "
             "the method is not unconditionally stable), found " +
                 num(h.theta));
    if (!h.transient && m.has("theta"))
      r.fail(*x,
             "theta is the time integration of a transient analysis; this heat analysis is "
             "steady (add analysis: transient)");
  }
  if (auto x = m.get("source")) {
    if (!x->node.IsScalar())
      r.fail(*x, "expected a number or an expression in x, y, z, t, T, found " + describe(x->node));
    h.source =
        Expression::parse(x->node.Scalar(), r.at(*x), Expression::Variables::with_temperature);
  }
  if (auto x = m.get("boundary"))
    for (const Val& item : r.entries(*x, "a list of heat conditions"))
      h.boundary.push_back(read_heat_condition(r, item));
  if (auto x = m.get("times")) {
    if (m.has("steps"))
      throw InputError(r.at(m.key_mark("steps"), child_path(v.path, "steps")),
                       "give either 'times' or 'steps', not both");
    const auto items = r.list(*x, "a list of step end times [t1, t2, ...]");
    if (items.size() > static_cast<std::size_t>(max_steps))
      r.fail(*x, "expected at most " + std::to_string(max_steps) + " step end times");
    for (const Val& it : items) {
      const double t = r.number(it);
      if (!(t > 0)) r.fail(it, "step end times must be > 0, found " + num(t));
      if (!h.times.empty() && !(t > h.times.back()))
        r.fail(it, "step end times must be strictly increasing, found " + num(t) + " after " +
                       num(h.times.back()));
      h.times.push_back(t);
    }
    if (h.times.empty()) r.fail(*x, "expected at least one step end time");
    if (h.times.back() < mechanical.back())
      r.fail(*x, "the heat steps end at t = " + num(h.times.back()) +
                     ", before the mechanical steps (t = " + num(mechanical.back()) +
                     "), which need its temperatures to the end");
  } else if (auto s = m.get("steps")) {
    const long n = r.integer(*s);
    if (n < 1 || n > max_steps)
      r.fail(*s, "expected a whole number in 1 .. " + std::to_string(max_steps) + ", found " +
                     std::to_string(n));
    h.times = StepTimes::equal(n, mechanical.back()).all();
  }
  if (auto x = m.get("tolerance")) {
    h.tolerance = r.number(*x);
    if (!(h.tolerance > 0 && h.tolerance < 1))
      r.fail(*x, "expected a relative tolerance in (0, 1), found " + num(h.tolerance));
  }
  if (auto x = m.get("max_iterations")) h.max_iterations = r.integer_at_least(*x, 1);
  if (auto x = m.get("absolute_zero")) {
    h.absolute_zero = r.number(*x);
    if (*h.absolute_zero > 0)
      r.fail(*x,
             "the absolute zero in the case's temperature unit is <= 0 (-273.15 for "
             "degrees Celsius, 0 for kelvin), found " +
                 num(*h.absolute_zero));
  }
  if (auto x = m.get("stefan_boltzmann")) h.stefan_boltzmann = r.positive(*x);
  for (const auto& b : h.boundary)
    if (b.kind == HeatBoundarySpec::Kind::radiation && !h.absolute_zero)
      throw InputError(b.value_where,
                       "radiation needs heat.absolute_zero, the absolute zero in the case's "
                       "temperature unit: -273.15 when temperatures are in degrees Celsius, 0 "
                       "when they are in kelvin");
  return h;
}

void check_heat(const Case& c) {
  const TemperatureSpec& ts = c.temperature;
  if (ts.from_heat && !c.heat.given)
    throw InputError(ts.field_where,
                     "temperature from: heat needs a 'heat' section (its analysis, boundary "
                     "conditions and initial temperature)");
  if (!c.heat.given) return;
  if (!ts.given)
    throw InputError(c.heat.where,
                     "the heat section's temperatures reach the stresses through "
                     "'temperature: {reference: T_ref, from: heat}'; add that section");
  if (!ts.from_heat)
    throw InputError(ts.field_where,
                     "the case has a heat section: its temperatures are the mechanical ones "
                     "with 'from: heat' in place of 'field'");
  const auto& bcs = c.heat.boundary;
  if (!c.heat.transient && std::none_of(bcs.begin(), bcs.end(), [](const HeatBoundarySpec& b) {
        return b.kind != HeatBoundarySpec::Kind::flux &&
               b.kind != HeatBoundarySpec::Kind::nodal_flux;
      }))
    throw InputError(
        SourceLocation{c.heat.where.file, c.heat.where.line, c.heat.where.column, "heat.boundary"},
        "a steady heat analysis needs a temperature, convection or radiation "
        "condition: with heat fluxes alone the temperature is known only up to a "
        "constant (and exists only when the fluxes and the source balance)");
  for (const MaterialSpec& m : c.materials) {
    if (m.conductivity.value.empty())
      throw InputError(m.conductivity.where,
                       "material '" + m.name +
                           "' needs 'conductivity' (W/(m K)), a number or a table over "
                           "temperature: the case has a heat section");
    if (!c.heat.transient) continue;
    for (const PropertyTable* p : {&m.density, &m.specific_heat})
      if (p->value.empty())
        throw InputError(p->where,
                         "material '" + m.name + "' needs '" +
                             (p == &m.density ? std::string("density' (kg/m^3)")
                                              : std::string("specific_heat' (J/(kg K))")) +
                             ": the heat analysis is transient");
  }
}

}  // namespace case_input
}  // namespace hencky
