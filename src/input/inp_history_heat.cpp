// A deck's heat transfer (input/inp_history.hpp): the procedures *HEAT TRANSFER and *COUPLED
// TEMPERATURE-DISPLACEMENT, the temperatures of *BOUNDARY's degree of freedom 11, *FILM,
// *RADIATE, *DFLUX and *PHYSICAL CONSTANTS, made into the case's heat section
// (docs/ccx-decks.md, "Heat transfer").
//
// CalculiX's meaning (User's Manual, ccx 2.20, *HEAT TRANSFER, *COUPLED TEMPERATURE-
// DISPLACEMENT, *FILM, *RADIATE, *DFLUX): a steady step solves the steady state at its end; a
// transient one integrates in time from the initial temperatures with the step's conditions
// applied at once. ccx's own coupled procedure solves temperatures and displacements together;
// without heat made by deformation or contact the temperatures do not depend on the
// displacements, and hencky's heat analysis ahead of each mechanical step gives the same answer
// (the sequential coupling of solve/heat.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "input/inp_history.hpp"
#include "input/inp_reader.hpp"

namespace hencky::inp {

void DeckCase::heat_procedure(InpReader& r, const Keyword& k, int at, int first, int end) {
  if (!in_step_) throw r.fail(at, "*" + k.name + " outside a *STEP");
  if (step_has_procedure_) return refuse(r, at, "a second procedure in one *STEP");
  step_has_procedure_ = true;
  DeckStep& s = steps_.back();
  s.procedure =
      k.name == "HEAT TRANSFER" ? DeckStep::Procedure::heat : DeckStep::Procedure::coupled;
  s.steady = k.has("STEADY STATE");
  s.direct = k.has("DIRECT");
  for (const auto& [p, v] : k.params) {
    if (p == "STEADY STATE" || p == "DIRECT" || p == "SOLVER") continue;
    refuse(r, at,
           fmt::format("*{}, {}{}: not read by hencky", k.name, p, v.empty() ? "" : "=" + v));
  }
  // initial increment, time period, minimum and maximum increment, DELTMX (heat transfer).
  double dt0 = 1, period = 1, dt_max = 0;
  if (first < end) {
    const auto f = r.data_in_place(first);
    if (f.size() > 0 && !f[0].empty()) dt0 = r.real(f[0], first, "initial increment");
    if (f.size() > 1 && !f[1].empty()) period = r.real(f[1], first, "time period");
    if (f.size() > 3 && !f[3].empty()) dt_max = r.real(f[3], first, "maximum increment");
    if (f.size() > 4 && !f[4].empty() && !s.steady && !s.direct)
      note(r, first,
           "*" + k.name +
               ": DELTMX left out; hencky's increments grow as ccx's do while the temperature "
               "change stays below it");
  }
  if (!(period > 0))
    throw r.fail(first, fmt::format("the step's time period must be > 0, found {:g}", period));
  if (!(dt0 > 0) || dt0 > period) dt0 = period;
  s.end = s.start + period;
  s.increment = dt0;
  s.max_increment = dt_max > 0 ? dt_max : 0.0;
}

void DeckCase::physical_constants(InpReader& r, const Keyword& k, int at) {
  constants_line_ = at;
  if (const std::string* z = k.get("ABSOLUTE ZERO"))
    absolute_zero_ = r.real(*z, at, "ABSOLUTE ZERO");
  if (const std::string* sb = k.get("STEFAN BOLTZMANN"))
    stefan_boltzmann_ = r.real(*sb, at, "STEFAN BOLTZMANN");
  for (const auto& [p, v] : k.params)
    if (p != "ABSOLUTE ZERO" && p != "STEFAN BOLTZMANN")
      note(r, at, fmt::format("*PHYSICAL CONSTANTS, {}: left out", p));
  if (stefan_boltzmann_ && !(*stefan_boltzmann_ > 0))
    throw r.fail(at, fmt::format("STEFAN BOLTZMANN must be > 0, found {:g}", *stefan_boltzmann_));
  if (absolute_zero_ && !(*absolute_zero_ <= 0))
    throw r.fail(at, fmt::format("ABSOLUTE ZERO must be <= 0, found {:g}", *absolute_zero_));
}

void DeckCase::face_heat(InpReader& r, const Keyword& k, int at, int first, int end) {
  bool op_new = false;
  const int amp = condition_options(r, k, at, op_new, {});
  if (!in_step_) throw r.fail(at, "*" + k.name + " outside a *STEP");
  // The letter of the face types: F1 .. F6 (*FILM), R1 .. R6 (*RADIATE), S1 .. S6 (*DFLUX).
  const char letter = k.name == "FILM" ? 'F' : k.name == "RADIATE" ? 'R' : 'S';
  const char* shape = k.name == "FILM"      ? "'element, ELSET or surface, F1 .. F6, sink "
                                              "temperature, film coefficient'"
                      : k.name == "RADIATE" ? "'element, ELSET or surface, R1 .. R6, sink "
                                              "temperature, emissivity'"
                                            : "'element, ELSET or surface, S1 .. S6, flux'";
  if (op_new && letter == 'S') remove_unnamed(flux_, at, true);
  if (op_new && letter != 'S')  // the faces not named again: the coefficient to 0
    for (auto& [face, c] : letter == 'F' ? film_ : radiate_) {
      Course::InStep& s = in_step(c[1]);
      if (!s.given) s = Course::InStep{true, false, 0.0, -1, at};
    }
  for (int l = first; l < end; ++l) {
    const auto f = r.data(l);
    if (f.size() < 2) throw r.fail(l, std::string("a *") + k.name + " line is " + shape);
    const std::string type = upper(f[1]);
    int side = 0;
    if (type.size() == 2 && type[0] == letter && type[1] >= '1' && type[1] <= '6') {
      side = type[1] - '0';
    } else if (!(type.size() == 1 && type[0] == letter) || InpReader::is_label(f[0])) {
      refuse(r, l,
             fmt::format("*{} of type {}: hencky reads {}1 .. {}6 on element faces (or {} on a "
                         "*SURFACE)",
                         k.name, type, letter, letter, letter));
      continue;
    }
    if (f.size() < (letter == 'S' ? 3u : 4u))
      throw r.fail(l, std::string("a *") + k.name + " line is " + shape);
    const double a = r.real(f[2], l, letter == 'S' ? "flux" : "sink temperature");
    const double b =
        letter == 'S' ? 0.0 : r.real(f[3], l, letter == 'F' ? "film coefficient" : "emissivity");
    if (letter == 'F' && !(b >= 0))
      throw r.fail(l, fmt::format("the film coefficient must be >= 0, found {:g}", b));
    if (letter == 'R' && !(b >= 0 && b <= 1))
      throw r.fail(l, fmt::format("the emissivity must lie in 0 .. 1, found {:g}", b));
    for (const ElementFace& face : r.face_targets(f[0], side, l)) {
      if (letter == 'S') {
        in_step(flux_[face]) = {true, true, a, amp, l};
        continue;
      }
      // The sink temperature follows the amplitude; the coefficient is the step's, at once.
      auto& c = (letter == 'F' ? film_ : radiate_)[face];
      in_step(c[0]) = {true, true, a, amp, l};
      in_step(c[1]) = {true, true, b, -1, l};
    }
  }
}

void DeckCase::cflux(InpReader& r, const Keyword& k, int at, int first, int end) {
  bool op_new = false;
  const int amp = condition_options(r, k, at, op_new, {});
  if (!in_step_) throw r.fail(at, "*CFLUX outside a *STEP");
  if (op_new) remove_unnamed(cflux_, at, true);
  for (int l = first; l < end; ++l) {
    const auto f = r.data(l);
    if (f.size() < 3) throw r.fail(l, "a *CFLUX line is 'node or NSET, 11, heat flow'");
    // The temperature's degree of freedom, 11 (ccx's own test decks write 0 for it).
    if (trim(f[1]) != "11" && trim(f[1]) != "0") {
      refuse(r, l,
             fmt::format("*CFLUX on degree of freedom {}: a heat flow is on the "
                         "temperature, 11",
                         f[1]));
      continue;
    }
    const double q = r.real(f[2], l, "heat flow");
    for (long n : r.node_targets(f[0], l)) in_step(cflux_[n]) = {true, true, q, amp, l};
  }
}

void DeckCase::check_heat_materials(InpReader& r, int step_line) {
  for (const MaterialSpec& m : spec_.materials) {
    const auto it = std::find_if(materials_.begin(), materials_.end(),
                                 [&](const Material& d) { return d.spec.name == m.name; });
    const int line = it != materials_.end() ? it->line : step_line;
    if (m.conductivity.value.empty())
      refuse(r, line,
             fmt::format("material '{}' has no *CONDUCTIVITY (heat steps need it)", m.name));
    if (spec_.heat.transient && (m.density.value.empty() || m.specific_heat.value.empty()))
      refuse(r, line,
             fmt::format("material '{}' needs *DENSITY and *SPECIFIC HEAT (transient heat steps)",
                         m.name));
  }
}

bool DeckCase::has_heat() const {
  return std::any_of(steps_.begin(), steps_.end(), [](const DeckStep& s) {
    return s.procedure == DeckStep::Procedure::heat || s.procedure == DeckStep::Procedure::coupled;
  });
}

void DeckCase::build_heat(InpReader& r) {
  const bool heat = has_heat();
  if (!heat) {
    if (!fixed_temperature_.empty())
      return refuse(r, fixed_temperature_.begin()->second.step.front().line,
                    "*BOUNDARY on degree of freedom 11 (a temperature) in a *STATIC deck: give "
                    "the temperatures with *TEMPERATURE");
    for (const auto* faces : {&film_, &radiate_})
      if (!faces->empty())
        return refuse(r, faces->begin()->second[0].step.front().line,
                      "*FILM or *RADIATE in a deck without *HEAT TRANSFER or *COUPLED "
                      "TEMPERATURE-DISPLACEMENT steps");
    if (!flux_.empty())
      return refuse(r, flux_.begin()->second.step.front().line,
                    "*DFLUX in a deck without *HEAT TRANSFER or *COUPLED "
                    "TEMPERATURE-DISPLACEMENT steps");
    if (!cflux_.empty())
      return refuse(r, cflux_.begin()->second.step.front().line,
                    "*CFLUX in a deck without *HEAT TRANSFER or *COUPLED "
                    "TEMPERATURE-DISPLACEMENT steps");
    return;
  }
  // One procedure kind and one of steady or transient for the whole run.
  const DeckStep& first = steps_.front();
  for (const DeckStep& s : steps_) {
    if (s.procedure == DeckStep::Procedure::none) continue;  // refused already
    if (s.procedure != first.procedure)
      return refuse(r, s.line,
                    "a deck that mixes *STATIC, *HEAT TRANSFER and *COUPLED "
                    "TEMPERATURE-DISPLACEMENT steps: hencky runs one kind of step in a deck");
    if (s.steady != first.steady)
      return refuse(r, s.line,
                    "steady and transient heat steps in one deck: hencky's heat analysis is one "
                    "or the other for the whole run");
  }
  if (!temperature_.empty())
    refuse(r, temperature_.begin()->second.step.front().line,
           "*TEMPERATURE in a deck with heat transfer: the temperatures are the heat "
           "analysis's");
  HeatSpec& h = spec_.heat;
  h.given = true;
  h.only = first.procedure == DeckStep::Procedure::heat;
  h.transient = !first.steady;
  h.where = r.where(first.line);
  h.source = Expression(0.0);
  h.theta = 1.0;              // ccx's heat transfer integrates with backward Euler
  h.fixed_from_start = true;  // ccx's first increment starts from the prescribed values
  // The initial temperatures: one value (hencky's heat.initial is a function of position).
  double T0 = 0;
  if (!initial_temperature_.empty()) {
    T0 = initial_temperature_.begin()->second;
    for (const auto& [n, T] : initial_temperature_)
      if (T != T0)
        return refuse(r, initial_line_,
                      fmt::format("*INITIAL CONDITIONS: initial temperatures from {:g} to "
                                  "{:g}; a deck's heat analysis starts from one temperature",
                                  T0, T));
    for (long n : r.body_node_labels())
      if (!initial_temperature_.count(n))
        return refuse(r, initial_line_,
                      fmt::format("*INITIAL CONDITIONS: node {} has no initial temperature (ccx "
                                  "takes 0 there; a deck's heat analysis starts from one "
                                  "temperature)",
                                  n));
  }
  h.initial = Expression(T0);
  if (constants_line_ >= 0) {
    h.absolute_zero = absolute_zero_;
    if (stefan_boltzmann_) h.stefan_boltzmann = *stefan_boltzmann_;
  }
  if (!radiate_.empty() && !absolute_zero_)
    refuse(r, radiate_.begin()->second[0].step.front().line,
           "*RADIATE needs the absolute zero: *PHYSICAL CONSTANTS, ABSOLUTE ZERO=");
  check_heat_materials(r, first.line);
  // The temperature of the stress analysis is the heat analysis's, from T0.
  TemperatureSpec& ts = spec_.temperature;
  ts.given = true;
  ts.from_heat = true;
  ts.reference = T0;
  ts.where = ts.reference_where = ts.field_where = h.where;
  build_heat_boundary(r);
  if (!h.transient && std::all_of(h.boundary.begin(), h.boundary.end(), [](const auto& b) {
        return b.kind == HeatBoundarySpec::Kind::flux ||
               b.kind == HeatBoundarySpec::Kind::nodal_flux;
      }))
    refuse(r, first.line,
           "a steady heat step needs a temperature (*BOUNDARY on 11), *FILM or *RADIATE: with "
           "heat fluxes alone the temperature is known only up to a constant");
}

template <class Key>
void DeckCase::add_heat_entries(InpReader& r, HeatBoundarySpec::Kind kind, const char* stem,
                                const Groups<Key>& groups) {
  int k = 0;
  for (const auto& [e, g] : groups) {
    HeatBoundarySpec b;
    b.region = r.unused_name(fmt::format("{}-{}", stem, ++k));
    b.kind = kind;
    b.where = b.value_where = r.where(g.second);
    b.value = Expression::parse(e[0], b.where);
    if (!e[1].empty()) b.ambient = Expression::parse(e[1], b.where);
    if constexpr (std::is_same_v<Key, long>)
      r.add_node_set(b.region, g.first, g.second);
    else
      r.add_face_surface(b.region, g.first, g.second);
    spec_.heat.boundary.push_back(std::move(b));
  }
}

void DeckCase::build_heat_boundary(InpReader& r) {
  // Prescribed temperatures, held from the start to the end.
  Groups<long> fixed;
  for (auto& [n, c] : fixed_temperature_) {
    in_step(c);
    if (!c.step.front().set)
      for (std::size_t s = 1; s < c.step.size(); ++s)
        if (c.step[s].set) {  // not held from the start: before it, the node is free
          refuse(r, c.step[s].line,
                 fmt::format("*BOUNDARY: node {}'s temperature is prescribed from step {} on; "
                             "hencky prescribes a temperature from the start of the run",
                             n, s + 1));
          break;
        }
    bool released = false;
    for (std::size_t s = 1; s < c.step.size(); ++s)
      released = released || (c.step[s - 1].set && !c.step[s].set);
    if (released) {
      refuse(r, c.step.back().line,
             fmt::format("*BOUNDARY: node {}'s temperature is released (OP=NEW); hencky "
                         "prescribes it to the end of the run",
                         n));
      continue;
    }
    if (!c.step.front().set) continue;
    auto& g = fixed[{expression(c), ""}];
    if (g.first.empty()) g.second = c.step.front().line;
    g.first.push_back(n);
  }
  add_heat_entries(r, HeatBoundarySpec::Kind::temperature, "TEMPERATURE", fixed);
  add_heat_entries(r, HeatBoundarySpec::Kind::nodal_flux, "CFLUX", group_courses(cflux_));
  add_heat_entries(r, HeatBoundarySpec::Kind::flux, "DFLUX", group_courses(flux_));
  // Films and radiation: by the coefficient's course and the sink temperature's.
  for (auto* faces : {&film_, &radiate_}) {
    const bool film = faces == &film_;
    Groups<ElementFace> groups;
    for (auto& [face, c] : *faces) {
      in_step(c[0]);
      in_step(c[1]);
      const std::array<std::string, 2> e{expression(c[1]), expression(c[0])};
      if (e[0] == "0") continue;
      auto& g = groups[e];
      if (g.first.empty()) g.second = c[1].step.back().line;
      g.first.push_back(face);
    }
    add_heat_entries(r,
                     film ? HeatBoundarySpec::Kind::convection : HeatBoundarySpec::Kind::radiation,
                     film ? "FILM" : "RADIATE", groups);
  }
}

}  // namespace hencky::inp
