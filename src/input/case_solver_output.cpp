// The solver section (scheme, steps, iteration and linear solver settings) and the output
// section (folder, probes, reactions).
#include <algorithm>
#include <cctype>
#include <map>
#include <sstream>

#include "core/suggest.hpp"
#include "input/case_sections.hpp"
#include "parallel/mpi.hpp"
#include "solve/schemes.hpp"

namespace hencky::case_input {

namespace fs = std::filesystem;

namespace {

// clang-format off
const std::vector<std::string> solver_keys = {
    "scheme",    "curve_form",   "steps",       "end",           "times",    "max_iterations",
    "tolerance", "relaxation",   "correction",  "cutback",       "linear",   "mechanism_limit",
    "predictor", "acceleration", "line_search", "petsc_options", "geometry", "correction_form",
    "formulation"};
// clang-format on
const std::vector<std::string> schemes(scheme_names.begin(), scheme_names.end());
const std::vector<std::string> curve_forms = {"stress", "strain"};
const std::vector<std::string> predictors = {"extrapolate", "none"};
const std::vector<std::string> accelerations = {"auto", "none", "anderson"};  // Acceleration
const std::vector<std::string> auto_none = {"auto", "none"};
const std::vector<std::string> geometries = {"small", "updated"};
const std::vector<std::string> correction_forms = {"previous", "current"};
const std::vector<std::string> formulations = {"hencky", "report"};
const std::vector<std::string> linear_solvers = {"auto", "direct", "iterative", "petsc"};
const std::vector<std::string> output_keys = {
    "dir", "every", "probes", "reactions", "heat_flows", "checkpoint", "checkpoint_keep",
    "iterations"};
const std::vector<std::string> probe_keys = {"name", "point"};

const KeySection solver_output_key_sections[] = {
    {"solver", &solver_keys},
    {"output", &output_keys},
    {"output.probes[i]", &probe_keys},
};

// ---------------------------------------------------------------------------------------------
// Solver

/// Why the number of steps is bounded (max_steps).
const std::string too_many_steps =
    ": every step is a solve with a history row and a log line, so more steps only make the run "
    "and its outputs longer without resolving the load path better (split a long load history "
    "into several cases, or use larger steps)";

/// times: [t1, t2, ...], or steps and end (equal steps).
StepTimes read_step_times(const Reader& r, const Map& m, const Val& v) {
  if (auto x = m.get("times")) {
    for (const char* k : {"steps", "end"})
      if (m.has(k))
        throw InputError(
            r.at(m.key_mark(k), child_path(v.path, k)),
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
    return StepTimes::list(std::move(times));
  }
  long steps = 1;
  if (auto x = m.get("steps")) {
    steps = r.integer(*x);
    if (steps < 1) r.fail(*x, "expected a whole number >= 1, found " + std::to_string(steps));
    if (steps > max_steps)
      r.fail(*x, "expected at most " + std::to_string(max_steps) + " steps, found " +
                     std::to_string(steps) + too_many_steps);
  }
  const double end = m.has("end") ? r.positive(*m.get("end")) : 1.0;
  return StepTimes::equal(steps, end);
}

/// The enumerator at the position of `name` in `names` (a choice the reader accepted).
template <class E>
E index_of(const std::vector<std::string>& names, const std::string& name, E) {
  return static_cast<E>(std::find(names.begin(), names.end(), name) - names.begin());
}

/// acceleration: auto, none or anderson; anderson where the iteration is a fixed map.
void read_acceleration(const Reader& r, const Val& x, SolverSpec& s) {
  using A = SolverSpec::Acceleration;
  s.acceleration = index_of(accelerations, r.choice(x, accelerations, "acceleration"), A::none);
  // Anderson mixing needs a fixed map: a fixed matrix within the step.
  if (s.acceleration == A::anderson &&
      !make_scheme(s)->allows_acceleration())
    r.fail(x,
           "acceleration: anderson applies to the fixed-matrix schemes initial-stress, "
           "initial-stress-stiffness, initial-strain and initial-strain-stiffness, not to '" +
               std::string(scheme_name(s.scheme)) + "'");
}

/// formulation: report refuses what would add one of hencky's strategies to the report's
/// iteration, each by its key: newton (not a report scheme), `acceleration: anderson`,
/// `line_search: auto`, `relaxation: auto` and `geometry: updated` (the report's iteration with
/// Hencky's finite strain is not written yet). Without a number ω is the report's plain 1.
void check_report(const Reader& r, const Map& m, SolverSpec& s) {
  const std::string use = "; solver.formulation: hencky runs it";
  if (s.scheme == SchemeKind::newton)
    r.fail(m.has("scheme") ? *m.get("scheme") : *m.get("formulation"),
           "formulation: report runs the report's five schemes (variable-stiffness, "
           "initial-strain, initial-strain-stiffness, initial-stress, initial-stress-stiffness); "
           "newton, hencky's reference scheme, is not one of them" +
               use);
  const auto refuse = [&](const char* key, const std::string& value, const std::string& what) {
    if (auto x = m.get(key); x && x->node.IsScalar() && trim(x->node.Scalar()) == value)
      r.fail(*x, std::string("formulation: report iterates as the report writes it, without ") +
                     what + use);
  };
  refuse("acceleration", "anderson", "Anderson's mixing");
  refuse("line_search", "auto", "a line search");
  refuse("relaxation", "auto", "the automatic relaxation (give ω as a number)");
  refuse("geometry", "updated",
         "hencky's finite-strain kinematics (the report's own iteration under geometry: updated "
         "is not implemented)");
  s.acceleration = SolverSpec::Acceleration::none;
  s.line_search = false;
  s.extrapolate = false;
  if (s.relaxation == 0) s.relaxation = 1;
}

/// correction: γ, a number or an expression of t (one value per step, at its end time), >= 0
/// at every planned step (a cut-back's time between them is checked when the step begins).
void read_correction(const Reader& r, const Val& x, SolverSpec& s) {
  Expression g = r.expression(x);
  if (g.depends_on_position())
    r.fail(x, "γ is one value per step: it may depend on t only, found '" + g.text() + "'");
  for (std::size_t k = 0; k < s.times.size(); ++k) {
    const double t = s.times[k], v = g(0, 0, 0, t);
    if (!(v >= 0) || !std::isfinite(v))
      r.fail(x,
             "expected a number or an expression of t >= 0 (0 turns the correction off), "
             "found " +
                 num(v) + (g.is_constant() ? "" : " at t = " + num(t)));
    if (!g.depends_on_time()) break;
  }
  s.correction = std::move(g);
}

/// petsc_options: only options: a token that is no option must be the value of the one before it.
void read_petsc_options(const Reader& r, const Val& x, SolverSpec& s) {
  s.petsc_options = r.string(x);
  std::istringstream in(s.petsc_options);
  std::string token, previous;
  while (in >> token) {
    const bool option = par::is_petsc_option_name(token);
    if (!option && (previous.empty() || previous[0] != '-'))
      r.fail(x, "expected PETSc options such as \"-ksp_type cg -pc_type hypre\"; '" + token +
                    "' is neither an option (starting with '-') nor the value of one");
    previous = option ? token : std::string();
  }
}

}  // namespace

std::span<const KeySection> solver_output_sections() {
  return solver_output_key_sections;
}

SolverSpec read_solver(const Reader& r, const std::optional<Val>& v) {
  SolverSpec s;
  if (!v) return s;
  Map m(r, *v, solver_keys);
  if (auto x = m.get("scheme"))
    s.scheme = index_of(schemes, r.choice(*x, schemes, "scheme"), s.scheme);
  if (auto x = m.get("curve_form"))
    s.curve_form = index_of(curve_forms, r.choice(*x, curve_forms, "curve form"), s.curve_form);
  s.times = read_step_times(r, m, *v);
  if (auto x = m.get("max_iterations"))
    s.max_iterations =
        x->node.IsScalar() && trim(x->node.Scalar()) == "auto" ? 0 : r.integer_at_least(*x, 1);
  if (auto x = m.get("tolerance")) {
    s.tolerance = r.number(*x);
    if (!(s.tolerance > 0 && s.tolerance < 1))
      r.fail(*x, "expected a relative tolerance with 0 < tolerance < 1, found " + num(s.tolerance));
  }
  if (auto x = m.get("relaxation"))
    s.relaxation = r.positive_or_auto(*x, "a relaxation factor > 0").value_or(0.0);
  if (auto x = m.get("correction")) read_correction(r, *x, s);
  if (auto x = m.get("cutback")) s.cutback = r.integer_at_least(*x, 0);
  if (auto x = m.get("mechanism_limit")) s.mechanism_limit = r.positive(*x);
  if (auto x = m.get("predictor"))
    s.extrapolate = r.choice(*x, predictors, "predictor") == "extrapolate";
  if (auto x = m.get("acceleration")) read_acceleration(r, *x, s);
  if (auto x = m.get("line_search"))
    s.line_search = r.choice(*x, auto_none, "line search setting") == "auto";
  if (auto x = m.get("geometry"))
    s.updated_geometry = r.choice(*x, geometries, "geometry setting") == "updated";
  if (auto x = m.get("correction_form"))
    s.correction_current = r.choice(*x, correction_forms, "correction form") == "current";
  if (auto x = m.get("linear")) {
    const std::string l = r.choice(*x, linear_solvers, "linear solver");
    s.linear = l == "auto"        ? SolverSpec::Linear::automatic
               : l == "direct"    ? SolverSpec::Linear::direct
               : l == "iterative" ? SolverSpec::Linear::iterative
                                  : SolverSpec::Linear::petsc;
  }
  if (auto x = m.get("petsc_options")) read_petsc_options(r, *x, s);
  if (auto x = m.get("formulation"))
    s.report = r.choice(*x, formulations, "formulation") == "report";
  if (s.report) check_report(r, m, s);
  return s;
}

// ---------------------------------------------------------------------------------------------
// Output

bool valid_probe_name(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

namespace {

/// output.probes: named points whose displacement goes into history.csv.
std::vector<ProbeSpec> read_probes(const Reader& r, const Val& x) {
  std::vector<ProbeSpec> probes;
  std::map<std::string, std::size_t> names;
  for (const auto& item : r.entries(x, "a list of probes")) {
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
    names.emplace(p.name, probes.size());
    const Val point = pm.require(r, "point", "the probe's coordinates [x, y, z]");
    p.point = r.vec3(point);
    p.where = r.at(point);
    probes.push_back(std::move(p));
  }
  return probes;
}

}  // namespace

OutputSpec read_output(const Reader& r, const std::optional<Val>& v, const fs::path& default_dir,
                       const std::vector<BoundarySpec>& boundary, const HeatSpec& heat) {
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
  // checkpoint: N >= 1 converged steps, or off (0 too); default: at every written step.
  if (auto x = m.get("checkpoint")) {
    const bool off = x->node.IsScalar() && x->node.Scalar() == "off";
    o.checkpoint = off ? 0 : r.integer_at_least(*x, 0);
  }
  if (auto x = m.get("checkpoint_keep")) o.checkpoint_keep = r.integer_at_least(*x, 0);
  if (auto x = m.get("probes")) o.probes = read_probes(r, *x);
  if (auto x = m.get("iterations"))
    o.iterations = r.choice(*x, {"true", "false"}, "iterations setting") == "true";
  // Regions with a displacement or a heat temperature condition, and with any heat condition,
  // in order.
  std::vector<std::string> fixed, heated;
  auto add = [](std::vector<std::string>& list, const std::string& region) {
    if (std::find(list.begin(), list.end(), region) == list.end()) list.push_back(region);
  };
  for (const auto& b : boundary)
    if (b.kind == BoundaryKind::displacement) add(fixed, b.region);
  for (const auto& b : heat.boundary) {
    if (b.kind == HeatBoundarySpec::Kind::temperature) add(fixed, b.region);
    add(heated, b.region);
  }
  if (auto x = m.get("heat_flows")) {
    if (!heat.given)
      r.fail(*x, "heat flows are those of a heat analysis; the case has no 'heat' section");
    for (const auto& item : r.names(*x)) {
      const std::string reg = r.string(item, "a region name");
      if (std::find(o.heat_flows.begin(), o.heat_flows.end(), reg) != o.heat_flows.end())
        r.fail(item, "region '" + reg + "' is listed twice");
      if (std::find(heated.begin(), heated.end(), reg) == heated.end())
        r.fail(item, "region '" + reg +
                         "' has no heat condition, so no heat crosses it; heat flows are "
                         "reported for regions of heat.boundary. " +
                         suggestion(reg, heated, "regions with a heat condition"));
      o.heat_flows.push_back(reg);
      o.heat_flow_where.push_back(r.at(item));
    }
  }
  if (auto x = m.get("reactions")) {
    for (const auto& item : r.names(*x)) {
      const std::string reg = r.string(item, "a region name");
      if (std::find(o.reactions.begin(), o.reactions.end(), reg) != o.reactions.end())
        r.fail(item, "region '" + reg + "' is listed twice");
      if (std::find(fixed.begin(), fixed.end(), reg) == fixed.end())
        r.fail(item, "region '" + reg +
                         "' has no displacement condition; reactions are "
                         "reported for regions with prescribed displacement (or temperature). " +
                         suggestion(reg, fixed, "regions with a displacement condition"));
      o.reactions.push_back(reg);
      o.reaction_where.push_back(r.at(item));
    }
  }
  return o;
}

}  // namespace hencky::case_input
