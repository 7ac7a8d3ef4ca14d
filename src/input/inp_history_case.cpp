// The deck's conditions resolved over its steps and grouped into the Case's boundary entries,
// materials and steps (input/inp_history.hpp); read_deck (input/inp_case.hpp).
//
// CalculiX's meaning (User's Manual, ccx 2.20, sections 7.x on *STATIC, *BOUNDARY, *CLOAD,
// *DLOAD, *TEMPERATURE, *AMPLITUDE): the deck's total time runs through the steps one after
// another; in a *STATIC step a condition goes linearly from its value at the last step's end to
// the value the step gives it (a load never given starts at 0), or, with an AMPLITUDE, is that
// value times the amplitude; a condition a step does not name keeps its value; OP=NEW removes the
// conditions of its kind that the step does not name again (a load then goes to 0 over the step).
// A condition is resolved per node and direction (per face for a pressure), as ccx keeps it,
// and the nodes (faces) that follow the same course over time form one region of the case.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "input/inp_case.hpp"
#include "input/inp_history.hpp"
#include "input/inp_reader.hpp"

namespace hencky {

namespace fs = std::filesystem;

namespace inp {

namespace {

/// A number as muparser reads it back to the last bit; negative ones in parentheses.
std::string num(double v) {
  return v < 0 ? fmt::format("({:.17g})", v) : fmt::format("{:.17g}", v);
}

/// Pieces of a function of t over consecutive intervals ending at `ends`, the last one open:
/// one expression, the same pieces merged.
std::string piecewise(const std::vector<double>& ends, const std::vector<std::string>& pieces) {
  std::string e = pieces.back();
  for (std::size_t i = pieces.size() - 1; i-- > 0;)
    if (pieces[i] != e) e = fmt::format("(t <= {} ? {} : {})", num(ends[i]), pieces[i], e);
  return e;
}

}  // namespace

double DeckCase::value_at_end(const Course& c, int s) const {
  const Course::InStep& st = c.step[static_cast<std::size_t>(s)];
  if (!st.set) return 0;
  if (st.amplitude < 0) return st.value;
  const Amplitude& a = amplitudes_[static_cast<std::size_t>(st.amplitude)];
  if (!a.defined()) return st.value;  // not defined (yet): an error at the deck's end
  const DeckStep& step = steps_[static_cast<std::size_t>(s)];
  return st.value * a.factor(a.total_time ? step.end : step.end - step.start);
}

std::string DeckCase::amplitude_expression(const Amplitude& a, double start) const {
  // In the step's own time τ = t − start unless TIME=TOTAL TIME; constant beyond its ends.
  const double shift = a.total_time ? 0.0 : start;
  const std::vector<double>& time = a.factor.temperature;
  const std::vector<double>& value = a.factor.value;
  if (time.empty()) return num(value.front());  // one point: a constant
  std::vector<double> ends;
  std::vector<std::string> pieces;
  ends.push_back(time.front() + shift);
  pieces.push_back(num(value.front()));
  for (std::size_t i = 0; i + 1 < time.size(); ++i) {
    const double t0 = time[i] + shift, t1 = time[i + 1] + shift;
    ends.push_back(t1);
    pieces.push_back(fmt::format("({} + {}*(t - {})/{})", num(value[i]),
                                 num(value[i + 1] - value[i]), num(t0), num(t1 - t0)));
  }
  pieces.push_back(num(value.back()));
  return piecewise(ends, pieces);
}

std::string DeckCase::expression(const Course& c) const {
  std::vector<double> ends;
  std::vector<std::string> pieces;
  for (std::size_t s = 0; s < steps_.size(); ++s) {
    const Course::InStep& st = c.step[s];
    const DeckStep& step = steps_[s];
    ends.push_back(step.end);
    if (!st.set) {
      pieces.push_back("0");
    } else if (st.amplitude >= 0) {
      pieces.push_back(fmt::format(
          "{}*{}", num(st.value),
          amplitude_expression(amplitudes_[static_cast<std::size_t>(st.amplitude)], step.start)));
    } else if (step.transient()) {  // applied at once (ccx's step amplitude)
      pieces.push_back(num(st.value));
    } else {
      const double before = s == 0 ? 0.0 : value_at_end(c, static_cast<int>(s) - 1);
      pieces.push_back(before == st.value ? num(st.value)
                                          : fmt::format("({} + {}*(t - {})/{})", num(before),
                                                        num(st.value - before), num(step.start),
                                                        num(step.end - step.start)));
    }
  }
  return piecewise(ends, pieces);
}

void DeckCase::build_steps() {
  std::vector<double> times;
  bool nlgeom = false;
  // A linear model (elastic, small strain) is solved once at the end of each step, as ccx solves
  // it (DIRECT or not); otherwise in increments of the step's first one (DIRECT: all of them;
  // ccx's automatic increments are hencky's own cut-back).
  const bool linear =
      std::none_of(materials_.begin(), materials_.end(),
                   [](const Material& m) { return m.used && m.spec.plasticity; }) &&
      std::none_of(steps_.begin(), steps_.end(), [](const DeckStep& s) { return s.nlgeom; });
  auto too_many = [&](double count) {
    if (static_cast<double>(times.size()) + count > static_cast<double>(max_steps))
      throw InputError(spec_.mesh.where,
                       fmt::format("the steps' increments make more than {} steps", max_steps));
  };
  for (const DeckStep& s : steps_) {
    const double period = s.end - s.start;
    nlgeom = nlgeom || s.nlgeom;
    const bool heat =
        s.procedure == DeckStep::Procedure::heat || s.procedure == DeckStep::Procedure::coupled;
    if (heat && !s.direct) {
      // A transient's time discretization is its answer, and ccx prints a steady step's
      // increments too: the increments ccx takes when each converges at once (its automatic
      // incrementation, User's Manual *CONTROLS): the first two of the initial size, then each
      // 1.5 times the last, up to the largest increment, the last one cut at the step's end.
      double t = s.start, dt = s.increment;
      for (int k = 0; t < s.end; ++k) {
        too_many(1.0);
        if (k >= 2) dt *= 1.5;
        if (s.max_increment > 0) dt = std::min(dt, s.max_increment);
        t = s.end - t <= dt * (1 + 1e-9) ? s.end : t + dt;
        times.push_back(t);
      }
      continue;
    }
    // Counted as a double first: a tiny increment must not overflow the cast.
    const double count =
        linear && !heat ? 1.0 : std::max(1.0, std::ceil(period / s.increment - 1e-9));
    too_many(count);
    const long n = static_cast<long>(count);
    for (long k = 1; k <= n; ++k)
      times.push_back(k == n ? s.end
                             : s.start + period * static_cast<double>(k) / static_cast<double>(n));
  }
  spec_.solver.times = StepTimes::list(times);
  spec_.solver.updated_geometry = nlgeom;
}

void DeckCase::build_materials(InpReader& r) {
  const bool heat_only = std::all_of(steps_.begin(), steps_.end(), [](const DeckStep& s) {
    return s.procedure == DeckStep::Procedure::heat;
  });
  for (Material& m : materials_) {
    if (!m.used) continue;
    if (m.spec.E.value.empty() && heat_only) {  // never used: nothing mechanical is solved
      m.spec.E.value = {1.0};
      m.spec.nu.value = {0.0};
      m.spec.E.where = m.spec.nu.where = m.spec.where;
    }
    if (m.combined_line >= 0 && !m.cyclic)
      refuse(r, m.combined_line,
             "*PLASTIC, HARDENING=COMBINED without *CYCLIC HARDENING: the isotropic part is its "
             "curve");
    if (m.spec.E.value.empty()) {  // a material hencky lacks (refused where it is given)
      refuse(r, m.line, fmt::format("material '{}' has no *ELASTIC", m.spec.name));
      continue;
    }
    if (m.spec.alpha.value.empty()) {  // no *EXPANSION: none
      m.spec.alpha.value = {0.0};
      m.spec.alpha.where = m.spec.where;
    }
    spec_.materials.push_back(m.spec);
  }
  if (spec_.materials.empty() && refusals_.empty())
    throw InputError(SourceLocation{spec_.file.string(), 0, 0, ""},
                     "the deck has no *SOLID SECTION: no element has a material");
}

void DeckCase::build_boundary(InpReader& r) {
  // Per node, the courses of its three directions; the nodes of one course form a region.
  std::map<long, std::array<const Course*, 3>> by_node;
  // The nodes a *BOUNDARY line holds from a later step on, or that a step releases: one refusal
  // per line and step, naming the first nodes.
  std::map<std::tuple<int, std::size_t, bool>, std::vector<long>> late, released;
  for (auto& [key, c] : displacement_) {
    in_step(c);
    for (std::size_t s = 0; s < c.step.size(); ++s) {
      const bool before = s == 0 || c.step[s - 1].set;
      if (c.step[s].set && !before) late[{c.step[s].line, s, true}].push_back(key.first);
      if (!c.step[s].set && s > 0 && c.step[s - 1].set)
        released[{c.step[s - 1].line, s, false}].push_back(key.first);
    }
    if (c.step.front().set) by_node[key.first][static_cast<std::size_t>(key.second)] = &c;
  }
  auto some = [](std::vector<long> nodes) {
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    const std::size_t n = nodes.size();
    if (n > 3) nodes.resize(3);
    return fmt::format("{} node{} ({}{})", n, n > 1 ? "s" : "", fmt::join(nodes, ", "),
                       n > 3 ? ", ..." : "");
  };
  for (const auto& [at, nodes] : late)
    refuse(r, std::get<0>(at),
           fmt::format("*BOUNDARY: {} held from step {} on; hencky holds a prescribed "
                       "displacement from the start of the run (give it in the first step)",
                       some(nodes), std::get<1>(at) + 1));
  for (const auto& [at, nodes] : released)
    refuse(r, std::get<0>(at),
           fmt::format("*BOUNDARY: {} released in step {} (OP=NEW); hencky holds a prescribed "
                       "displacement to the end of the run",
                       some(nodes), std::get<1>(at) + 1));
  std::map<std::array<std::string, 3>, std::pair<std::vector<long>, int>> groups;
  for (const auto& [node, dirs] : by_node) {
    std::array<std::string, 3> e;
    int line = 0;
    for (std::size_t d = 0; d < 3; ++d)
      if (dirs[d]) {
        e[d] = expression(*dirs[d]);
        line = dirs[d]->step.front().line;
      }
    auto& g = groups[e];
    if (g.first.empty()) g.second = line;
    g.first.push_back(node);
  }
  int k = 0;
  for (const auto& [e, g] : groups) {
    BoundarySpec b;
    b.region = r.unused_name(fmt::format("BOUNDARY-{}", ++k));
    b.kind = BoundaryKind::displacement;
    b.where = r.where(g.second);
    for (std::size_t d = 0; d < 3; ++d)
      if (!e[d].empty()) b.components[d] = Expression::parse(e[d], b.where);
    r.add_node_set(b.region, g.first, g.second);
    spec_.output.reactions.push_back(b.region);
    spec_.output.reaction_where.push_back(b.where);
    spec_.boundary.push_back(std::move(b));
  }
}

void DeckCase::build_loads(InpReader& r) {
  std::map<long, std::array<std::string, 3>> by_node;
  std::map<long, int> line_of;
  for (auto& [key, c] : cload_) {
    in_step(c);
    const std::string zero = "0";
    auto& e =
        by_node.try_emplace(key.first, std::array<std::string, 3>{zero, zero, zero}).first->second;
    e[static_cast<std::size_t>(key.second)] = expression(c);
    line_of[key.first] = c.step.back().line;
  }
  std::map<std::array<std::string, 3>, std::vector<long>> groups;
  for (const auto& [node, e] : by_node)
    if (e != std::array<std::string, 3>{"0", "0", "0"}) groups[e].push_back(node);
  int k = 0;
  for (const auto& [e, nodes] : groups) {
    BoundarySpec b;
    b.region = r.unused_name(fmt::format("CLOAD-{}", ++k));
    b.kind = BoundaryKind::nodal_force;
    b.where = r.where(line_of.at(nodes.front()));
    for (std::size_t d = 0; d < 3; ++d) b.components[d] = Expression::parse(e[d], b.where);
    r.add_node_set(b.region, nodes, line_of.at(nodes.front()));
    spec_.boundary.push_back(std::move(b));
  }
  k = 0;
  for (const auto& [e, g] : group_courses(pressure_)) {
    BoundarySpec b;
    b.region = r.unused_name(fmt::format("DLOAD-{}", ++k));
    b.kind = BoundaryKind::pressure;
    b.where = r.where(g.second);
    b.pressure = Expression::parse(e[0], b.where);
    r.add_face_surface(b.region, g.first, g.second);
    spec_.boundary.push_back(std::move(b));
  }
  if (gravity_.empty() || spec_.materials.empty()) return;
  const Gravity& g = gravity_.front();
  if (gravity_.size() > 1)
    return refuse(r, gravity_[1].line, "a second GRAV load: hencky reads one");
  const PropertyTable& rho = spec_.materials.front().density;
  for (const MaterialSpec& m : spec_.materials)
    if (m.density.value.size() != 1 || m.density.value != rho.value)
      return refuse(r, g.line,
                    "GRAV needs one constant *DENSITY for every material (hencky's body force is "
                    "one force per volume)");
  Course ramp;  // 0 before the step of the GRAV line, ramped to 1 over it, 1 after
  ramp.step.resize(steps_.size());
  for (std::size_t s = static_cast<std::size_t>(g.step); s < steps_.size(); ++s)
    ramp.step[s] = {true, true, 1.0, -1, g.line};
  const std::string factor = expression(ramp);
  std::array<Expression, 3> f;
  for (std::size_t d = 0; d < 3; ++d)
    f[d] = Expression::parse(fmt::format("{}*{}", num(rho.value[0] * g.g[d]), factor),
                             r.where(g.line));
  spec_.body_force = f;
}

void DeckCase::build_temperature(InpReader& r) {
  TemperatureSpec& ts = spec_.temperature;
  bool tables = false;
  for (const MaterialSpec& m : spec_.materials)
    tables = tables || !m.E.is_constant() || !m.nu.is_constant() || !m.alpha.is_constant() ||
             (m.plasticity && m.plasticity->curve.tables.size() > 1);
  if (!has_heat() && temperature_.empty() && initial_temperature_.empty() && !tables) return;
  ts.given = true;
  ts.where = ts.field_where = ts.reference_where =
      initial_line_ >= 0 ? r.where(initial_line_) : SourceLocation{spec_.file.string(), 0, 0, ""};
  const std::vector<long>& labels = r.node_labels();
  auto initial = [&](long n) {
    const auto it = initial_temperature_.find(n);
    return it == initial_temperature_.end() ? 0.0 : it->second;
  };
  double lo = INFINITY, hi = -INFINITY;
  for (long n : r.body_node_labels()) {  // a node on no element has no say
    lo = std::min(lo, initial(n));
    hi = std::max(hi, initial(n));
  }
  ts.reference = labels.empty() ? 0.0 : lo;
  // ccx projects the temperatures onto trilinear functions in a plain C3D20 (lintemp.f) and
  // interpolates them with the element's own functions in C3D20R and C3D10 (e_c3d.f): the
  // deck's quadratic cells are one or the other (a mix is refused).
  const auto& types = r.volume_types();
  long projected = 0, quadratic = 0;
  for (const auto& [type, n] : types)
    if (type == "C3D20" || type == "C3D10T")
      projected += n;
    else if (type.rfind("C3D20", 0) == 0 || type.rfind("C3D10", 0) == 0 ||
             type.rfind("C3D15", 0) == 0)
      quadratic += n;
  ts.linear_in_quadratic_cells = projected > 0;
  if (projected > 0 && quadratic > 0 && (!temperature_.empty() || lo != hi))
    refuse(r, initial_line_ >= 0 ? initial_line_ : 0,
           fmt::format("temperatures in {} C3D20 (C3D10T) and {} other quadratic elements: ccx "
                       "interpolates them differently in the two, hencky one way in a run",
                       projected, quadratic));
  bool expands = false;
  for (const Material& m : materials_) {
    if (!m.used) continue;
    const auto& a = m.spec.alpha.value;
    const bool any = std::any_of(a.begin(), a.end(), [](double v) { return v != 0; });
    expands = expands || any;
    if (any && !m.spec.alpha.is_constant() && m.expansion_zero != ts.reference)
      refuse(r, m.line,
             fmt::format("material '{}': *EXPANSION over temperature with ZERO={:g} and the "
                         "initial temperature {:g}: hencky's thermal strain is "
                         "alpha(T)*T - alpha(T0)*T0, ccx's with ZERO=T0 (give ZERO= the initial "
                         "temperature, or 0)",
                         m.spec.name, m.expansion_zero, ts.reference));
  }
  if (lo != hi && expands && !has_heat())  // a heat deck refuses it in build_heat
    refuse(r, initial_line_,
           fmt::format("*INITIAL CONDITIONS: the initial temperatures range from {:g} to {:g}; "
                       "hencky's stress-free temperature is one value for the body",
                       lo, hi));
  if (has_heat()) return;  // the heat analysis's temperatures (build_heat)
  if (temperature_.empty() && lo == hi) {
    ts.field = Expression(ts.reference);
    return;
  }
  // The nodal temperatures at the start and at each step's end, linear in time between.
  TemperatureFile file;
  file.path = spec_.file;
  file.times.push_back(0.0);
  for (const DeckStep& s : steps_) file.times.push_back(s.end);
  file.node_tags = labels;
  file.values.reserve(labels.size() * file.times.size());
  for (long n : labels) {
    const double T0 = initial(n);
    file.values.push_back(T0);
    auto it = temperature_.find(n);
    if (it != temperature_.end()) in_step(it->second);
    for (std::size_t s = 0; s < steps_.size(); ++s)
      file.values.push_back(
          it != temperature_.end() && it->second.step[s].set ? it->second.step[s].value : T0);
  }
  ts.file = std::move(file);
}

void DeckCase::finish(InpReader& r) {
  if (in_step_) refuse(r, steps_.back().line, "*STEP without its *END STEP");
  if (steps_.empty())
    throw InputError(SourceLocation{spec_.file.string(), 0, 0, ""},
                     "the deck has no *STEP: nothing to solve (a deck run as a case needs its "
                     "history, *STEP .. *END STEP)");
  if (spec_.title.empty()) spec_.title = spec_.file.stem().string();
  for (Amplitude& a : amplitudes_)
    if (!a.defined()) {  // refused where it is defined, or not defined at all
      refuse(r, a.used_line, fmt::format("no *AMPLITUDE named '{}' that hencky reads", a.name));
      a.factor.value = {1.0};  // a placeholder for the rest of the reading; nothing is solved
    }
  bind_sections(r);
  build_steps();
  build_materials(r);
  build_boundary(r);
  build_loads(r);
  build_temperature(r);
  build_heat(r);
  build_requests();
  // NLGEOM stays on once given (DeckCase::step): the first step that has it says it all.
  const auto late_nlgeom =
      std::find_if(steps_.begin(), steps_.end(), [](const DeckStep& s) { return s.nlgeom; });
  if (late_nlgeom != steps_.begin() && late_nlgeom != steps_.end())
    refuse(r, late_nlgeom->line,
           fmt::format("NLGEOM from step {} on: hencky's geometry is updated in every step or "
                       "in none (give NLGEOM in the first step)",
                       late_nlgeom - steps_.begin() + 1));
  if (!refusals_.empty()) {
    std::string list;
    constexpr std::size_t shown = 40;  // a deck of another kind altogether: the first ones
    for (std::size_t i = 0; i < std::min(refusals_.size(), shown); ++i)
      list += "\n  " + refusals_[i];
    if (refusals_.size() > shown)
      list += fmt::format("\n  ... and {} more", refusals_.size() - shown);
    throw InputError(r.where(first_refusal_),
                     fmt::format("the deck asks for {} thing{} hencky cannot do; nothing was "
                                 "solved:{}",
                                 refusals_.size(), refusals_.size() > 1 ? "s" : "", list));
  }
}

}  // namespace inp

DeckRead parse_deck(std::string_view text, const fs::path& file) {
  const fs::path path = fs::absolute(file).lexically_normal();
  DeckRead d;
  d.spec.file = path;
  d.spec.mesh.file = path;
  d.spec.mesh.where = SourceLocation{file.string(), 0, 0, ""};
  d.spec.output.dir = path.parent_path() / (path.stem().string() + ".out");
  d.spec.output.dir_where = d.spec.mesh.where;
  inp::Deck deck;
  deck.names.push_back(file.string());
  deck.add(text, 0, 0);
  const MeshReadOptions options;
  std::vector<std::string> mesh_warnings;
  inp::InpReader reader(deck, options, &mesh_warnings);
  inp::DeckCase history(d.spec);
  reader.set_history(&history);
  d.mesh = reader.read();
  d.warnings = history.warnings();
  d.warnings.insert(d.warnings.end(), mesh_warnings.begin(), mesh_warnings.end());
  return d;
}

DeckRead read_deck(const fs::path& file, std::string* text) {
  std::string own = inp::read_text(file, "deck");
  DeckRead d = parse_deck(own, file);
  if (text) *text = std::move(own);
  return d;
}

}  // namespace hencky
