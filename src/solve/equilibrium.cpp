#include "solve/equilibrium.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/interrupt.hpp"
#include "core/invariant.hpp"
#include "parallel/mpi.hpp"
#include "solve/finite_check.hpp"

namespace hencky {
namespace {

/// The diagonal of the mesh's bounding box (the whole mesh's, when `layout` distributes it).
double model_size(const Mesh& mesh, const NodalLayout& layout) {
  Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
  for (const Vec3& p : mesh.x) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (layout.kind() == NodalLayout::Kind::distributed) {
    double box[6] = {-lo.x(), -lo.y(), -lo.z(), hi.x(), hi.y(), hi.z()};
    par::max_in_place(std::span<double>(box));
    lo = -Vec3(box[0], box[1], box[2]);
    hi = Vec3(box[3], box[4], box[5]);
  }
  return (hi - lo).norm();
}

}  // namespace

Equilibrium::Equilibrium(const Model& m, LinearSystem& system, Log& log, Timings& timings,
                         HeatSolver* heat)
    : m_(m),
      log_(log),
      scheme_(make_scheme(m.spec().solver)),
      policy_(choose_policy(m, *scheme_)),
      // On more than one rank each rank works on its own cells and the nodal vectors are
      // summed over the ranks.
      iterate_(m, system.own_cells(), *scheme_, policy_.max_flips, log, timings, heat),
      matrix_(m, system, iterate_, log, timings),
      predictor_(policy_.extrapolate),
      search_(policy_.line_search),
      mixing_(policy_.mix, policy_.anderson_depth, scheme_->iterates_initial_strain(), iterate_,
              system.own_cells()),
      held_(policy_.held_set),
      limit_(policy_) {
  // A rank stores the points of the cells it holds and works on its own cells: these must
  // agree (make_run_solver makes the model hold the partition's cells).
  const std::vector<char>* only = system.own_cells();
  for (int e = 0; e < m.mesh().cells.size(); ++e)
    if (!only || (*only)[e])
      HENCKY_VERIFY(m.holds_points(e), "the model does not hold the points of this rank's cells");
  if (policy_.plastic) model_size_ = model_size(m.mesh(), m.layout());
  if (policy_.report && policy_.plastic)
    log.info("formulation: report: the report's {} as written (docs/schemes.md, \"Two "
             "formulations\")",
             scheme_->name());
}

State Equilibrium::initial_state() const {
  State s;
  const int n_dofs = m_.dofs().n_dofs(), n_pts = m_.n_points();
  s.u.assign(n_dofs, 0.0);
  s.nodal_temperature.assign(m_.mesh().n_nodes(), m_.reference_temperature());
  s.stress.assign(n_pts, Voigt::Zero());
  s.temperature.assign(n_pts, m_.reference_temperature());
  s.constants.resize(n_pts);
  for (int e = 0; e < m_.mesh().cells.size(); ++e)
    for (int p = m_.point_offset(e); p < m_.point_offset(e + 1); ++p)
      s.constants[p] = m_.material_of(e).at(m_.reference_temperature());
  s.f_ext.assign(n_dofs, 0.0);
  s.f_int.assign(n_dofs, 0.0);
  s.plastic_strain.assign(n_pts, Voigt::Zero());
  s.eps_p_eq.assign(n_pts, 0.0);
  s.eps_ep.assign(n_pts, 0.0);
  s.eps_ep_max.assign(n_pts, 0.0);
  s.flowing.assign(n_pts, 0);
  s.internal.assign(static_cast<std::size_t>(n_pts) * m_.law_state_size(), 0.0);
  iterate_.contact().initial(s);
  return s;
}

bool Equilibrium::step(const State& c, double t1, State& trial, StepOutcome& out) {
  out = StepOutcome{};
  ++attempts_;
  if (m_.spec().heat.only) {  // nothing mechanical: the step is the heat solution at t1
    iterate_.temperatures_only(c, t1, trial);
    return true;
  }
  iterate_.begin(c, t1, trial);
  // Under `updated` the prescribed displacements of the step first spread into the body; the
  // forces of that motion on the body held as it was are a force scale of the step (what its
  // first iterate's forces were without the spreading; a rigid motion has no other).
  const double spread =
      m_.spec().solver.updated_geometry ? matrix_.spread_prescribed(c, trial) : 0.0;
  // The report's first solve is made of the scheme's initial parameters (evaluate_initial).
  Evaluation ev =
      iterate_.evaluate(c, trial, false, policy_.report ? PointMode::initial : PointMode::law);
  const double f_step = std::max(iterate_.step_force(c, trial, ev), spread);
  const double f_norm = std::max(f_step, IterateEvaluator::history_force(c));
  bool extrapolated = false;
  if (predictor_.enabled() && spread == 0)  // before the loop
    ev = predictor_.predict(c, trial, ev, f_norm, extrapolated, iterate_, log_);
  // The elastic start: at u(t) the step's prescribed displacements and
  // thermal strains act on a body that has not deformed with them yet, all in the cells next to
  // the supports or where the temperature changes; the point law there yields points (a whole
  // layer of elements under a prescribed displacement) far beyond the answer. newton did not
  // recover from the plastic tangents of that layer (a cube stretched by its face: an elastic
  // step cut back four times), and the fixed-matrix schemes carried its overshoot (stresses
  // above a table's end for the strain form) through their iterations. The first solve of a
  // step that is not extrapolated is the elastic one, as Abaqus/Standard's first iteration of
  // an increment spreads a prescribed displacement with the stiffness of the converged state;
  // the point law decides from the first iterate on: the schemes' memory starts there, not
  // from the overshoot (with the initial-strain schemes' λ0 of that overshoot kept, the layer's
  // points cycled between λ0 = 0 and a λ0 far too large: a cube stretched just past its yield
  // failed after four cut-backs; it takes 12 iterations now). An overshoot beyond the strain
  // form's range is no failure of the step either: the elastic start replaces it.
  if (!extrapolated && (ev.points.plastic_points > 0 || ev.points.undefined_cell >= 0) &&
      policy_.elastic_start)
    ev = iterate_.evaluate(c, trial, false, PointMode::elastic);
  // The start, for a step that begins again with the contact set of its first iterate (below).
  const bool contact = iterate_.contact().active();
  const std::vector<double> u_start = contact ? trial.u : std::vector<double>();
  limit_.start_step();
  mixing_.start_step();
  held_.start_step();
  search_.start_step();
  first_iteration_ = 0;
  out.correction = out.previous_correction = 0;
  for (out.iterations = 0;; ++out.iterations) {
    if (par::any(interrupt_requested()))  // every rank stops at the same iteration
      throw Interrupted(fmt::format("interrupted in the step to t = {:g}", t1));
    if (out.iterations > 0) {
      std::optional<Evaluation> searched = search_.take();
      ev = searched ? std::move(*searched) : iterate_.evaluate(c, trial, true);
    }
    if (out.iterations == 1 && contact && !policy_.report &&
        iterate_.contact().progress().released > 0 && ev.points.plastic_points > 0)
      ev = begin_again(c, trial, u_start);
    const double scale = measure(trial, ev, f_norm, out);
    if (policy_.report) require_strain_form(ev);  // the report's map has no iterate past it
    const bool holds_broken = held_.observe(ev.points);
    const bool done = converged(out);
    if (done && !holds_broken && admissible(out) &&
        !released_pulling(c, trial, ev, scale, out)) {
      require_strain_form(ev);
      accept(c, trial, scale, out);
      trial.force_integral = c.force_integral + f_step * (trial.time - c.time);
      return true;
    }
    if (limit_.diverges(out.iterations, out.load_residual)) {
      out.diverged = true;
      out.best_residual = limit_.best_residual();
      return false;
    }
    const bool contact_converged = !contact || iterate_.contact().progress().converged();
    if (limit_.reached(out.iterations, contact_converged, log_)) {
      require_strain_form(ev);  // the reason, where the iterate left the strain form's range
      return false;
    }
    const bool updated = m_.spec().solver.updated_geometry;
    const std::vector<double> u_before = updated ? trial.u : std::vector<double>();
    advance(c, trial, ev, out.iterations, out.residual);
    if (updated) {
      out.previous_correction = out.correction;
      out.correction = iterate_.correction_ratio(c, trial, u_before);
    }
    if (held_.update(out.iterations, ev.points, holds_broken, done, iterate_.points(), log_))
      mixing_.new_map();
  }
}

double Equilibrium::measure(const State& trial, const Evaluation& ev, double f_norm,
                            StepOutcome& out) {
  // With contact, the force a surface's travel puts on the first iterate (κ times the
  // travel) is no force scale of the problem: that of the internal forces of the iterate is.
  const double scale =
      iterate_.contact().active() ? std::max(f_norm, iterate_.norm(trial.f_int)) : f_norm;
  out.residual = scale > 0 ? std::sqrt(ev.r2) / scale : 0.0;
  // A NaN or an infinity in the iterate makes r or the scale non-finite; a NaN scale would
  // read as "no load" above (and a residual of 0 as converged).
  if (!std::isfinite(ev.r2) || !std::isfinite(scale)) out.residual = NAN;
  out.load_residual = f_norm > 0 ? std::sqrt(ev.r2) / f_norm : out.residual;
  out.delta_sigma = ev.points.delta_sigma;
  out.delta_eps = ev.points.delta_eps;
  out.plastic_points = ev.points.plastic_points;
  out.yield_excess = YieldExcess{};
  out.yield_excess.value = ev.points.yield_excess;
  out.points_above = ev.points.points_above;
  if (m_.layout().shared()) {
    // The sums over ranks may differ in their last bits from rank to rank: root's figures
    // decide for all.
    double d[4] = {out.residual, out.delta_sigma, out.delta_eps, out.load_residual};
    par::broadcast(std::span<double>(d));
    out.residual = d[0], out.delta_sigma = d[1], out.delta_eps = d[2], out.load_residual = d[3];
  }
  report(out);
  if (iterate_observer_)
    iterate_observer_->iterate_done({attempts_, trial.time, out.iterations, out.residual,
                                     out.delta_sigma, out.delta_eps, out.plastic_points},
                                    trial);
  if (!std::isfinite(out.residual)) throw_not_finite(m_, trial, out.iterations, out.residual);
  const double tol = m_.spec().solver.tolerance;
  double worst = std::max(out.residual, out.correction) / tol;
  if (policy_.plastic) worst = std::max({worst, out.delta_sigma / tol, out.delta_eps / tol});
  limit_.record(worst);
  return scale;
}

/// An iterate whose stress left the strain form's range at some point has no answer of the
/// scheme (a step's start is spared: the elastic start replaces it).
void Equilibrium::require_strain_form(const Evaluation& ev) const {
  if (const Model::CellFacts e = m_.cell_facts(ev.points.undefined_cell); e.tag >= 0)
    throw SolveError(fmt::format(
        "scheme '{}' needs the strain form ε̃ = F(σ̃) of the curve of material '{}' above the "
        "largest stress the curve reaches (element {}): F is not defined there (perfect "
        "plasticity, a table's flat end). The schemes that can run it: {}",
        scheme_->name(), m_.materials()[e.material].spec->name, e.tag,
        schemes_without_strain_form));
}

/// The iteration's log line (and the contact's).
void Equilibrium::report(const StepOutcome& out) const {
  // Under `updated` the last correction too (the one that made this iterate).
  const std::string correction = m_.spec().solver.updated_geometry && out.iterations > 0
                                     ? fmt::format("  correction {:.3e}", out.correction)
                                     : "";
  if (policy_.plastic) {
    log_.detail(
        "  iteration {}: relative residual {:.3e}  Δσ {:.3e}  Δε {:.3e}  plastic "
        "points {}{}",
        out.iterations, out.residual, out.delta_sigma, out.delta_eps, out.plastic_points,
        correction);
  } else {
    log_.detail("  iteration {}: relative residual {:.3e}{}", out.iterations, out.residual,
                correction);
  }
  if (iterate_.contact().active()) {
    const ContactProgress& cp = iterate_.contact().progress();
    log_.detail("    contact: {} nodes{}{}, largest |gap| {:.2e} of the allowed", cp.in_contact,
                cp.set_changed ? ", set changed" : "", cp.kappa_raised ? ", κ raised" : "",
                cp.worst_gap);
  }
}

/// Every measure within the tolerance, after at least one solve. Under `geometry: updated`
/// the last correction of the displacements too, relative to the step's increment, unless it
/// is no smaller than half the one before (round-off, or too slow a convergence for it to say
/// more than the residual): where the answer is a rigid motion the step's force scale, which a
/// prescribed motion sets, says nothing of it (docs/schemes.md, "Convergence under updated").
bool Equilibrium::converged(const StepOutcome& out) const {
  const double tol = m_.spec().solver.tolerance;
  const bool measures_ok = !policy_.plastic || (out.delta_sigma <= tol && out.delta_eps <= tol);
  const bool contact_ok = !iterate_.contact().active() || iterate_.contact().progress().converged();
  const bool correction_ok = out.correction <= tol || (out.iterations >= 2 &&
                                                       out.correction > 0.5 * out.previous_correction);
  return out.iterations >= 1 && out.residual <= tol && correction_ok && measures_ok && contact_ok;
}

/// A converged iterate is the step's answer only where every point lies within its yield
/// surface, σ̃ ≤ σ̃_y·(1 + YieldExcess::slack): hencky's schemes converge to the radial return,
/// whose points lie on it, and an iterate above it has not converged yet (the iteration goes
/// on; at the iteration limit the step is cut back). The report's map leaves points above it
/// by construction where the stress turns within a step (Z(t) of (2.10)): accepted, and
/// accept() says so.
bool Equilibrium::admissible(const StepOutcome& out) const {
  if (policy_.report || !(out.yield_excess.value > YieldExcess::slack)) return true;
  const YieldExcess where = iterate_.points().largest_excess();
  log_.detail(
      "  converged, but {} points lie above their yield stress, the largest by {:.3g} "
      "(node {}, ({:.4g}, {:.4g}, {:.4g})): the iteration goes on",
      out.points_above, where.value, where.node, where.x.x(), where.x.y(), where.x.z());
  return false;
}

/// The checks a converged iterate must pass before it is the answer of the step.
void Equilibrium::accept(const State& c, State& trial, double scale, StepOutcome& out) {
  const auto& spec = m_.spec().solver;
  out.point_von_mises = iterate_.points().largest_von_mises(trial);
  if (policy_.plastic) {
    out.yield_excess = iterate_.points().largest_excess();
    if (policy_.report && out.yield_excess.value > YieldExcess::slack)
      log_.detail(
          "  the report's map leaves {} points above their yield stress, the largest by {:.3g} "
          "(node {}, ({:.4g}, {:.4g}, {:.4g}))",
          out.points_above, out.yield_excess.value, out.yield_excess.node,
          out.yield_excess.x.x(), out.yield_excess.x.y(), out.yield_excess.x.z());
  }
  // The reported residual is the true equilibrium defect F − F_int (γ only shifts the target).
  out.residual = scale > 0 ? iterate_.equilibrium_defect(trial) / scale : 0.0;
  // Small strains: an equilibrium found with displacements of the order of the body is a
  // mechanism (a load at or above the plastic limit load), not an answer.
  if (policy_.plastic && !spec.updated_geometry) {
    double u_max = 0;
    for (int n = 0; n < m_.mesh().n_nodes(); ++n)
      u_max = std::max(u_max, Vec3(trial.u[3 * n], trial.u[3 * n + 1], trial.u[3 * n + 2]).norm());
    u_max = m_.layout().largest(u_max);
    if (u_max > spec.mechanism_limit * model_size_) {
      throw SolveError(fmt::format(
          "the displacement reached {:.3g}, more than {:g} % of the model's size {:.3g} "
          "(solver.mechanism_limit): the body has become a mechanism (the load is at or "
          "above the plastic limit load), which a small-strain analysis cannot follow",
          u_max, 100 * spec.mechanism_limit, model_size_));
    }
  }
  // Never "converged" with a NaN or an infinity anywhere in the answer.
  if (par::any(!all_finite(trial))) throw_not_finite(m_, trial, out.iterations, out.residual);
  if (predictor_.enabled()) predictor_.remember(m_, c, trial);
}

/// The next iterate: a new matrix when the scheme's rule or the contact asks for one, the
/// solve, the acceleration, the line search.
void Equilibrium::advance(const State& c, State& trial, const Evaluation& ev, int iteration,
                          double residual) {
  const bool new_elements = matrix_.needs_elements(
      iteration, first_iteration_, ev.points.tangent_changed, scheme_->matrix_policy());
  if (mixing_.fell_back(trial, iteration, residual, log_)) return;
  // Asked on every rank: on a distributed mesh the ranks agree on it (collective).
  const bool stale = iterate_.contact().matrix_stale(trial);
  const bool refactor = new_elements || stale;
  // Under `updated` the first matrix of a step, and one kept through it, is that of the
  // step's start (StepStart::at_start, docs/schemes.md "The matrix, and newton under updated").
  const bool at_start = iteration == 0 || scheme_->matrix_policy() != MatrixPolicy::per_iteration;
  if (refactor) matrix_.assemble_and_factorize(c, trial, new_elements, iteration, at_start);
  try {
    matrix_.solve(residual);
  } catch (const LinearSystemError& e) {  // under `updated`, an indefinite matrix (CG)
    if (!matrix_.fall_back(c, trial, iteration, e)) throw;
    matrix_.solve(residual);
  }
  std::vector<double>& delta = matrix_.correction();
  mixing_.mix_correction(trial, delta, iteration, residual, refactor);
  if (search_.applies(iteration, residual, m_.spec().solver.tolerance))
    return search_.search(c, trial, delta, iterate_, log_);
  const auto& dofs = m_.dofs();
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) trial.u[i] += delta[k];
}

EquilibriumMemory Equilibrium::memory() const {
  EquilibriumMemory mem;
  mem.last_du = predictor_.last_du();
  mem.last_dt = predictor_.last_dt();
  mem.factorized = matrix_.factorized();
  if (mem.factorized) {
    mem.assembled_tangents = matrix_.assembled_tangents();
    mem.assembled_contact = iterate_.contact().assembled();
  }
  mem.tangents = iterate_.points().tangents();
  return mem;
}

void Equilibrium::resume(const State& c, EquilibriumMemory mem) {
  predictor_.resume(std::move(mem.last_du), mem.last_dt);
  if (mem.factorized) {
    // The matrix the run had factorized when it wrote the checkpoint, from what it was made
    // of: the points' matrices then and the contact states then (which need not be the
    // converged ones: the matrix is kept while they change little). Under `geometry:
    // updated`, or with E or ν varying with the temperature, the next step assembles its own.
    iterate_.points().set_tangents(std::move(mem.assembled_tangents));
    State at = c;
    if (iterate_.contact().active()) at.contact = std::move(mem.assembled_contact);
    matrix_.assemble_and_factorize(c, at, true, 0, true);
  }
  iterate_.points().set_tangents(std::move(mem.tangents));
}

}  // namespace hencky
