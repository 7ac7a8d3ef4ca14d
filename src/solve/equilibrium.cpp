#include "solve/equilibrium.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "core/interrupt.hpp"
#include "parallel/mpi.hpp"
#include "solve/element_matrix.hpp"
#include "solve/finite_check.hpp"

namespace hencky {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

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

/// solver.max_iterations: auto, by the scheme's matrix policy. An iteration of a fixed-matrix
/// scheme is a back-substitution and a stress evaluation, tens of times cheaper than newton's
/// factorization (31 + 19 ms against 0.9 s at 81k unknowns, docs/schemes.md), and it converges
/// linearly: while yield spreads the mixed iterations needed up to 60 a step (initial-stress,
/// the plate with a hole) and 185 (initial-strain, the same). With 50 for every scheme, the
/// issue-16 cases cut back steps that were converging (initial-stress on unload-all failed at
/// 50 iterations with a residual of 3e-7 against 1e-6; both initial-stress schemes were cut
/// back on unload-all and the indentation); with 200 none is (unload-all 182 -> 123
/// iterations in all, no cut-back, as the cut-back attempts no longer count).
int auto_max_iterations(MatrixPolicy policy) {
  return policy == MatrixPolicy::per_iteration ? 50 : 200;
}

}  // namespace

Equilibrium::Equilibrium(const Model& m, LinearSystem& system, Log& log, Timings& timings,
                         HeatSolver* heat)
    : m_(m),
      system_(system),
      heat_(heat),
      log_(log),
      timings_(timings),
      // On more than one rank each rank works on its own cells and the nodal vectors are
      // summed over the ranks.
      only_(system.own_cells()),
      plastic_(m.has_plasticity()),
      scheme_(make_scheme(m.spec().solver.scheme, m.spec().solver.curve_form,
                          m.spec().solver.relaxation)),
      points_(m, only_, *scheme_),
      // The flips a contact node may make in a step before the set is called oscillating
      // (ContactStep::update): 6 for the schemes whose matrix follows the iterate, scaled with
      // the scheme's automatic iteration limit: 24 for the fixed-matrix schemes, which iterate
      // linearly, and a node at the edge of the contact follows their unsettled plastic
      // strains for longer before it settles. Measured on
      // tests/cli/inputs/issue16/indentation-unload, initial-strain: a node at the edge flipped 7
      // times in the first 22 iterations of the step to t = 1 (Δε measure 3-16), and the step and
      // its first cut-back were cut back again; with no limit at all the set settled by iteration
      // 25 in every step.
      contact_(m, ContactStep::default_max_flips * auto_max_iterations(scheme_->matrix_policy()) /
                      auto_max_iterations(MatrixPolicy::per_iteration)),
      layout_(m.layout()),
      own_dofs_(layout_.owned_entries(m.dofs().eq.size(), 3, m.mesh().n_nodes())),
      own_free_(layout_.owned_free(m.dofs().eq, 3)),
      // The history's depth: the initial strains' state (Δε^0 along the trial's Z, the held
      // plastic set, with contact the nodes' c) is further from linear than the initial
      // stresses' displacements, and a longer history fits more of it. Measured with depth
      // 5 -> 8 -> 10 on the issue-16 table: the indentation 1742 iterations and 4 cut-backs ->
      // 833 and 2 -> 831 and 2 (initial-strain), 587 -> 499 -> 527 (initial-strain-stiffness);
      // unload-all 427 -> 312 -> 331 and 212 -> 176 -> 201; the multilinear cube 126 -> 136 ->
      // 143 and 55 -> 59 -> 61; the others within two iterations.
      anderson_(scheme_->iterates_initial_strain() ? 8 : 5) {
  // A rank stores the points of the cells it holds and works on its own cells: these must
  // agree (make_run_solver makes the model hold the partition's cells).
  for (int e = 0; e < m.mesh().cells.size(); ++e)
    if ((!only_ || (*only_)[e]) && !m.holds_points(e))
      throw std::logic_error("the model does not hold the points of this rank's cells");
  // Not with contact: extrapolating a long step after short ones pushes the nodes near the
  // contact far into the surfaces (8 increments deep on a plastic indentation, where the
  // step then failed; from the converged state it took 10 iterations).
  extrapolate_ = plastic_ && scheme_->kind() == SchemeKind::newton && m.spec().solver.extrapolate &&
                 m.contacts().empty();
  // solver.acceleration: auto mixes wherever the scheme's iteration is a fixed map (the reader
  // refuses `anderson` elsewhere).
  using A = SolverSpec::Acceleration;
  const A a = m.spec().solver.acceleration;
  // With a relaxation of their own the initial-strain schemes keep the report's plain
  // iteration unless `anderson` is asked for: a given ω far from auto's makes the relaxed
  // initial strain a poor secant history (measured: a restrained heated bar with ω = 0.03
  // converges plain and cycles mixed).
  const bool given_omega = scheme_->iterates_initial_strain() && m.spec().solver.relaxation > 0;
  // Without plasticity every scheme is the same linear solve per step: nothing to mix (with
  // contact the mixing only disturbed the augmented iteration: 56 iterations instead of 42 on
  // the elastic ball-indentation example).
  mix_ = plastic_ && (a == A::anderson ||
                      (a == A::automatic && scheme_->allows_acceleration() && !given_omega));
  // For the same reason no elastic start with a given ω: the plain iteration's first update of
  // λ0 comes from the overshoot of u(t) (measured: a uniaxial load-unload-reload at ω = 0.01,
  // initial-strain-stiffness, took 677 iterations and failed on reloading with the elastic
  // start, 0.99 per iteration from the elastic iterate; 37 iterations without).
  elastic_start_ = !given_omega;
  // solver.max_iterations: auto (auto_max_iterations).
  max_iterations_ = m.spec().solver.max_iterations > 0
                        ? m.spec().solver.max_iterations
                        : auto_max_iterations(scheme_->matrix_policy());
  // solver.line_search: the schemes whose matrix follows the iterate, variable-stiffness and
  // newton; the fixed-matrix schemes have Anderson's mixing instead.
  line_search_ = plastic_ && m.spec().solver.line_search &&
                 scheme_->matrix_policy() == MatrixPolicy::per_iteration;
  if (plastic_) model_size_ = model_size(m.mesh(), layout_);
  updated_ = m.spec().solver.updated_geometry;
  x_ = m.mesh().x;
  if (m.has_temperature())
    for (const auto& mat : m.materials())
      matrix_changes_with_temperature_ = matrix_changes_with_temperature_ ||
                                         !mat.spec->E.is_constant() || !mat.spec->nu.is_constant();
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
  contact_.initial(s);
  return s;
}

bool Equilibrium::step(const State& c, double t1, State& trial, StepOutcome& out) {
  out = StepOutcome{};
  begin(c, t1, trial);
  Evaluation ev = evaluate(c, trial, false);
  const double f_step = step_force(c, trial, ev);
  const double f_norm = std::max(f_step, history_force(c));
  bool extrapolated = false;
  if (extrapolate_) ev = predict(c, trial, ev, f_norm, extrapolated);  // before the loop
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
      elastic_start_)
    ev = evaluate(c, trial, false, true);
  // The start, for a step that begins again with the contact set of its first iterate (below).
  const std::vector<double> u_start = contact_.active() ? trial.u : std::vector<double>();
  double previous_residual = INFINITY;
  distances_.clear();
  anderson_.reset();
  mixed_last_ = restart_next_ = false;
  last_change_ = INFINITY;
  first_iteration_ = 0;
  holding_ = false;
  hold_set_ = plastic_ && scheme_->iterates_initial_strain();
  searched_.reset();
  for (out.iterations = 0;; ++out.iterations) {
    if (par::any(interrupt_requested()))  // every rank stops at the same iteration
      throw Interrupted(fmt::format("interrupted in the step to t = {:g}", t1));
    if (out.iterations > 0)
      ev = searched_ ? *std::exchange(searched_, std::nullopt) : evaluate(c, trial, true);
    if (out.iterations == 1 && contact_.active() && contact_.progress().released > 0 &&
        ev.points.plastic_points > 0)
      ev = begin_again(c, trial, u_start);
    // With contact, the force a surface's travel puts on the first iterate (κ times the
    // travel) is no force scale of the problem: that of the internal forces of the iterate is.
    const double scale = contact_.active() ? std::max(f_norm, norm(trial.f_int)) : f_norm;
    out.residual = scale > 0 ? std::sqrt(ev.r2) / scale : 0.0;
    // A NaN or an infinity in the iterate makes r or the scale non-finite; a NaN scale would
    // read as "no load" above (and a residual of 0 as converged).
    if (!std::isfinite(ev.r2) || !std::isfinite(scale)) out.residual = NAN;
    out.delta_sigma = ev.points.delta_sigma;
    out.delta_eps = ev.points.delta_eps;
    out.plastic_points = ev.points.plastic_points;
    if (layout_.shared()) {
      // The sums over ranks may differ in their last bits from rank to rank: root's figures
      // decide for all.
      double d[3] = {out.residual, out.delta_sigma, out.delta_eps};
      par::broadcast(std::span<double>(d));
      out.residual = d[0], out.delta_sigma = d[1], out.delta_eps = d[2];
    }
    report(out);
    if (!std::isfinite(out.residual)) throw_not_finite(m_, trial, out.iterations, out.residual);
    {
      const double tol = m_.spec().solver.tolerance;
      double worst = out.residual / tol;
      if (plastic_) worst = std::max({worst, out.delta_sigma / tol, out.delta_eps / tol});
      distances_.push_back(worst);
    }
    // An answer of the held plastic set (below) whose stresses put some held points on the
    // other side of their yield stress is not the step's: those points change sides, and the
    // iteration goes on.
    const bool holds_broken = holding_ && ev.points.holds_broken > 0;
    if (holding_) {
      same_broken_ = ev.points.holds_broken == last_broken_ ? same_broken_ + 1 : 1;
      last_broken_ = ev.points.holds_broken;
    }
    const bool done = converged(out);
    if (done && !holds_broken && !released_pulling(c, trial, ev, scale, out)) {
      require_strain_form(ev);
      accept(c, trial, scale, out);
      trial.force_integral = c.force_integral + f_step * (trial.time - c.time);
      return true;
    }
    if (out.iterations >= max_iterations_ && !converging_on(out)) {
      require_strain_form(ev);  // the reason, where the iterate left the strain form's range
      return false;
    }
    advance(c, trial, ev, out.iterations, out.residual, previous_residual);
    if (holds_broken && (done || same_broken_ >= settled_breaks))
      move_holds(ev.points.holds_broken, done);
    else if (out.iterations + 1 == hold_from && hold_set_)
      hold(out.plastic_points);
  }
}

/// A converged iterate in which the surface pulls on a node in contact is not the step's: the
/// node is released and the iteration goes on (true). The report's update keeps a node inside
/// the surface in contact whatever its force, and the forces it updates only grow while the
/// node stays inside a convex surface; but the tangent plane of a concave surface, and the
/// mixed contact state of the initial-strain schemes (Anderson's c of a node), can leave a
/// node at the surface with F·n < 0, a contact that glues (seen while a node's contact state
/// was held: −3.8e5 N on the ball of the indentation). A pull below the step's tolerance times
/// its force scale is round-off: released, the residual it leaves meets the tolerance.
bool Equilibrium::released_pulling(const State& c, State& trial, Evaluation& ev, double scale,
                                   StepOutcome& out) {
  if (!contact_.active()) return false;
  double limit = m_.spec().solver.tolerance * scale;
  if (layout_.shared()) par::broadcast(std::span<double>(&limit, 1));  // every rank decides alike
  const int n = contact_.release_pulling(c, trial, limit);
  if (n == 0) return false;
  log_.detail("  converged, but the surface pulls on {} nodes in contact: released", n);
  // The residual without the released nodes' forces: what the next solve corrects (and what
  // its iterative tolerance and the line search's test are taken from).
  ev.r2 = residual_vector(trial, &ev.r_loads2);
  out.residual = std::sqrt(ev.r2) / scale;
  restart_next_ = true;  // a new contact set: a new map for the mixing, no fallback across it
  mixed_last_ = false;
  return true;
}

/// The initial-strain schemes' active set. Their λ0 of a point at its yield stress jumps
/// between the plastic branch's value and zero as its iterate's stress crosses the yield
/// stress, and where hundreds of points sit there (first yield of a whole body under a force,
/// tests/cli/inputs/issue16/unload-all: 237-285 plastic points from one iteration to the next)
/// Anderson's least squares, which fits one linear map to the history, cannot settle them:
/// 200 iterations at a relative residual of 1e-4, four cut-backs, status 2. From iteration
/// `hold_from` on every point keeps the status of its last iterate, and the iteration is one
/// of a fixed set of points, a map linear on a linear curve, which the mixing converges. An
/// answer that leaves held points beyond their yield stress on the other side moves those
/// points and goes on: the primal-dual active-set iteration (Hintermüller, Ito and Kunisch,
/// SIAM J. Optim. 13, 2003; as Hüeber and Wohlmuth apply it to contact, see begin_again).
/// The move does not wait for the answer: once the same number of held points has stood
/// beyond the yield stress in `settled_breaks` iterates in a row, these are the points the
/// answer would move, and the iteration of the held set only spends its iterations on a map
/// that is about to change (an inexact solve of each active set, as the semismooth Newton
/// view of the method allows). Measured on tests/cli/inputs/issue16/indentation-unload,
/// initial-strain, the step to t = 1: the count of broken holds stood at 90 from iteration 35
/// on while the held set converged at iteration 103, then at 13 from 127 to 175, and at 1
/// from 183 to 207. Moving after 3 iterates alike, the issue-16 table's initial-strain runs:
/// unload-all 312 -> 190 iterations (initial-strain-stiffness 176 -> 110), the indentation
/// 833 -> 380 and its two cut-backs gone with the fixed-matrix schemes' flip limit (499 ->
/// 330), indentation-half 923 -> 613 (622 -> 444). With the flip limit of 6, after 2 iterates
/// alike: 233, 653, 683; after 3: 190, 552, 613; after 5: 199, 585, 646.
/// After `max_hold_moves` moves the points are set free again.
void Equilibrium::hold(int plastic_points) {
  holding_ = true;
  hold_moves_ = 0;
  const int held = points_.hold_plastic_set();
  new_held_set();
  log_.detail("  the plastic set is held from here ({} points plastic, {} in the last iterate)",
              held, plastic_points);
}

/// A new held set (hold, move_holds): a new map, so Anderson's history starts again, and the
/// next residual is not compared with this iterate's (the fallback would put the points'
/// memory, and their holds, back); its broken holds are counted afresh.
void Equilibrium::new_held_set() {
  restart_next_ = true;
  mixed_last_ = false;
  last_broken_ = -1;
  same_broken_ = 0;
}

void Equilibrium::move_holds(int broken, bool converged) {
  new_held_set();
  if (++hold_moves_ > max_hold_moves) {
    points_.free_plastic_set();
    holding_ = hold_set_ = false;
    log_.detail("  {} held points still beyond their yield stress after {} moves: every point free",
                broken, max_hold_moves);
    return;
  }
  points_.move_broken_holds();
  if (converged)
    log_.detail(
        "  converged on the held set, but {} of its points lie beyond their yield stress: "
        "they change sides",
        broken);
  else
    log_.detail(
        "  {} points of the held set lie beyond their yield stress in {} iterates in a row: "
        "they change sides",
        broken, settled_breaks);
}

/// A step whose first iterate released nodes that were in contact at t, and made points flow,
/// begins again at its start u_start, with the contact states that iterate left (the released
/// nodes free, the others with their updated forces and contact points).
///
/// Why. The report's start (3.1) holds every node of ⁽ᵗ⁾Contact at its contact point moved
/// with the surface, so where a surface recedes the first solve drags the nodes after it: it
/// is a solve of the committed contact set (the first step of a primal-dual active-set
/// iteration, Hüeber and Wohlmuth, Comput. Methods Appl. Mech. Engrg. 194, 2005; Wriggers,
/// Computational Contact Mechanics, 2nd ed., 2006, on active-set strategies), and the
/// reactions it returns decide, with the compliance of the whole body, which nodes let go.
/// That decision is good; the displacements are not: on the plastic indentation of
/// tests/cli/inputs/issue16/indentation-unload, lifting the ball 2 mm (t = 1 -> 1.5) pulled
/// 26 nodes 2 mm up (relative residual 442) and reversed the flow in 536 points. newton then
/// linearized the material there, the next iterates sprang the dent back into the ball (gaps
/// 300-600 times the allowed one), the set flipped until the oscillation check stopped the
/// step: the two unloading steps took 5 cut-backs and 81 iterations (111 for the run). Begun
/// again from u(t) with the set the first iterate found (no node: the ball has left the dent
/// at t = 1.2), the step to t = 1.5 takes 5 iterations, the unloading 7 (37 for the run, no
/// cut-back).
/// Releasing before the first solve the nodes whose reaction the receding surface alone
/// turns tensile (F·n < κ × the gap to the moved surface) decides node by node with κ, ten
/// times the node's own stiffness, and not with the body's: on the plastic cylinder of
/// VerifyContactPlastic it released every node and the step failed after 4 cut-backs.
/// Holding such nodes at ⁽ᵗ⁾r for the first solve (force capped at zero tension) was worse on
/// both (the indentation 6 cut-backs; the cylinder 430 factorizations and a cut-back).
/// Frohne, Heister and Bangerth (Int. J. Numer. Meth. Engng 105, 2016; elastoplastic contact
/// by an active-set Newton) damp such iterates by a line search instead; beginning again is
/// simpler and was enough here. Only where the first iterate made points flow: an elastic
/// iterate is an exact point to linearize at, and beginning again there cost an iteration
/// (the plastic measures of the next iterate compare it with u(t); issue16/unload-all, the
/// plane lifted off an elastically unloading cube: 26 -> 27 iterations with newton).
Equilibrium::Evaluation Equilibrium::begin_again(const State& c, State& trial,
                                                 const std::vector<double>& u_start) {
  log_.detail(
      "  the first iterate released {} nodes in contact at t: the step begins again "
      "from u(t) with its contact set",
      contact_.progress().released);
  trial.u = u_start;
  points_.begin_step(c, trial);  // the points' memory of the step starts again
  // The solve from u(t) is the elastic one, as at the start of a step (step()). Measured:
  // with the start-of-step tangent instead, initial-stress-stiffness sprang the plastic
  // cylinder of VerifyContactPlastic into the roller (gaps 1e6 times the allowed one) and its
  // first unloading step failed after three cut-backs; with the elastic matrix it took 6
  // iterations (13 before this rule).
  restart_next_ = true;  // a new map for Anderson's history
  // The `-stiffness` schemes' start slopes are decided by the first iterates from here on
  // (start_slope_on_unloading), and their matrix may change with them. (Measured: the ball
  // indentation's first unloading step, initial-strain-stiffness, began again at iteration 1;
  // its flowing points found themselves unloading at iteration 2, the point law switched to 3G
  // while the matrix kept the loading slope, and the step diverged through five cut-backs.)
  first_iteration_ = 1;
  return evaluate(c, trial, false, elastic_start_);
}

/// The force scale of the step, fixed at its start: the loads, the internal forces before and
/// after the first iterate (reactions included), and its residual (which carries thermal and
/// prescribed-displacement loading). It vanishes in a step whose start and target have no load
/// and no stress: free expansion, or unloading to zero (then history_force holds the scale).
/// ‖v‖ of a complete nodal vector (3 per node) over the whole model.
double Equilibrium::norm(const std::vector<double>& v) const {
  return std::sqrt(layout_.dot(v, v, own_dofs_));
}

double Equilibrium::step_force(const State& c, const State& trial, const Evaluation& ev) const {
  return std::max({norm(trial.f_ext), norm(c.f_int), norm(trial.f_int), std::sqrt(ev.r_loads2)});
}

/// The force scale of the history: the time average of the steps' force scales over the
/// converged steps (as Abaqus/Standard's time-averaged force, Abaqus Analysis User's Guide
/// 7.2.3). A step whose own forces have gone to round-off, as when the load has been removed
/// and the body is free of stress, measures its residual against the forces the analysis has
/// carried, which cannot vanish once a load was applied: the round-off of the unloaded state
/// converges at once, where against its own scale it read as a relative residual of order 1.
double Equilibrium::history_force(const State& c) const {
  return c.time > 0 ? c.force_integral / c.time : 0.0;  // the analysis starts at t = 0
}

/// The step's loads, temperatures and prescribed displacements at t1, the points' and the
/// contact's set-up, and the equilibrium target (2.29)-(2.30).
void Equilibrium::begin(const State& c, double t1, State& trial) {
  const auto& dofs = m_.dofs();
  trial.time = t1;
  trial.u = c.u;
  if (heat_) {
    const auto t0 = std::chrono::steady_clock::now();
    heat_->at(t1, trial.nodal_temperature, trial.heat_flow);
    timings_.heat += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } else {
    m_.nodal_temperature(t1, trial.nodal_temperature);
  }
  points_.temperatures(trial, log_);
  m_.prescribed_displacement(t1, trial.u);  // prescribed entries of u at t1, free ones at t
  if (updated_)
    for (int n = 0; n < m_.mesh().n_nodes(); ++n)
      x_[n] = m_.mesh().x[n] + Vec3(c.u[3 * n], c.u[3 * n + 1], c.u[3 * n + 2]);
  m_.external_forces(t1, trial.f_ext, updated_ ? &x_ : nullptr);
  if (plastic_) points_.begin_step(c, trial);
  if (contact_.active()) contact_.begin(c, trial);
  // Equilibrium target of the step, (2.29)-(2.30). The step's equation is written on x_:
  //   F_int − ∫Bᵀσ(t) = P(t+Δt) − P(t) + ΔF_contact + γ·R(t),
  // with P and ∫Bᵀσ(t) on x_ and R(t) = ⁽ᵗ⁾P + ⁽ᵗ⁾F_contact − ∫Bᵀσ(t), the defect the previous
  // step left: on the configuration of the step before, as that step computed it (2.30; the
  // state keeps f_ext and f_int as their step computed them), or on x_ (2.31,
  // correction_form: current). The iterate's F_int (PointPass::update) is ∫F S ∇N dx on
  // x_, the internal force of σ(t+Δt) on its own configuration pulled back to x_. On
  // the undeformed mesh both forms are c's own figures and the target is
  // F(t+Δt) − (1 − γ)·R(t): with γ = 1 the defect is corrected in full. The supports' forces
  // of the step are part of the residual (residual_vector), so that R(t) carries ⁽ᵗ⁾F as
  // (3.6) asks.
  const double gamma = correction(t1);
  const std::vector<double>* loads = &c.f_ext;  // P(t) and ∫Bᵀσ(t) on x_
  const std::vector<double>* forces = &c.f_int;
  if (updated_) {
    m_.external_forces(c.time, loads_at_t_, &x_);
    points_.internal_forces(c, x_, forces_at_t_);
    loads = &loads_at_t_;
    forces = &forces_at_t_;
    report_defect(c);
  }
  const bool current = m_.spec().solver.correction_current;
  const std::vector<double>& loads_r = current ? *loads : c.f_ext;  // those of R(t)
  const std::vector<double>& forces_r = current ? *forces : c.f_int;
  target_.resize(dofs.n_dofs());
  // On the undeformed mesh loads == c.f_ext and forces == c.f_int: the general form reduces to
  // the second, which is kept as written so that small-geometry results stay bit for bit.
  for (int i = 0; i < dofs.n_dofs(); ++i)
    target_[i] = updated_
                     ? trial.f_ext[i] - ((*loads)[i] + c.f_contact[i] - (*forces)[i]) +
                           gamma * (loads_r[i] + c.f_contact[i] - forces_r[i])
                     : trial.f_ext[i] - (1 - gamma) * (c.f_ext[i] + c.f_contact[i] - c.f_int[i]);
  rhs_.resize(dofs.n_free);
  delta_.resize(dofs.n_free);
}

/// Under `geometry: updated`, the log's figure of the equilibrium defect of σ(t) on the
/// configuration reached at t, ‖P(t) + F_contact(t) − ∫Bᵀσ(t)‖ over x_ on the free dofs: what
/// the step before left (the residual (2.31) corrects), against the larger of the loads and
/// those internal forces (the supports' included).
void Equilibrium::report_defect(const State& c) const {
  const auto& dofs = m_.dofs();
  double d2 = 0;
  for (std::size_t i = 0; i < own_dofs_; ++i)
    if (dofs.eq[i] >= 0) {
      const double d = loads_at_t_[i] + c.f_contact[i] - forces_at_t_[i];
      d2 += d * d;
    }
  d2 = layout_.total(d2);
  const double scale = std::max(norm(loads_at_t_), norm(forces_at_t_));
  log_.detail("  equilibrium defect at t = {:g} on its configuration: {:.3e} ({:.3e} relative)",
              c.time, std::sqrt(d2), scale > 0 ? std::sqrt(d2) / scale : 0.0);
}

/// γ of the step that ends at t1 (solver.correction, checked at the planned steps' times when
/// the case was read; a cut-back's time between them is checked here).
double Equilibrium::correction(double t1) const {
  const Expression& g = m_.spec().solver.correction;
  const double v = g.eval_checked(0, 0, 0, t1, "the correction γ");
  if (v < 0)
    throw InputError(g.where(), fmt::format("the correction γ = '{}' is {:g} at t = {:g} (a step "
                                            "cut back): expected >= 0 at every step",
                                            g.text(), v, t1));
  return v;
}

/// The iterate trial.u: points and internal forces, then (after a solve) the contact's steps
/// 3-4, then the residual.
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

Equilibrium::Evaluation Equilibrium::evaluate(const State& c, State& trial, bool update_contact,
                                              bool elastic) {
  Evaluation ev;
  const auto t0 = Clock::now();
  ev.points = points_.update(c, trial, x_, elastic);
  timings_.material += seconds_since(t0);
  if (const Model::CellFacts e = m_.cell_facts(ev.points.inverted_cell); e.tag >= 0)
    throw SolveError(fmt::format(
        "element {} is turned inside out at t = {:g} or halfway through the step to t = {:g} "
        "(geometry: updated): the step moved its nodes past each other; smaller steps may "
        "follow the deformation, a mesh this distorted will not",
        e.tag, c.time, trial.time));
  negative_secant_cell_ = ev.points.negative_secant_cell;
  if (update_contact) update_contact_states(c, trial);
  ev.r2 = residual_vector(trial, &ev.r_loads2);
  return ev;
}

/// The contact states updated at the iterate (after its points, before its residual).
void Equilibrium::update_contact_states(const State& c, State& trial) {
  if (!contact_.active()) return;
  const auto t0 = Clock::now();
  contact_.update(c, trial);
  timings_.contact += seconds_since(t0);
}

/// newton's predictor (solver.predictor: extrapolate). The step starts from the converged
/// state (evaluated: `at_start`). When the last step moved the free nodes by Δu_n and the new
/// step's out-of-balance force does positive work on Δu_n (the load keeps its direction: not
/// a reversal), the start moves on to u(t) + (Δt/Δt_n)·Δu_n, the linear extrapolation of the
/// path (Abaqus/Standard starts its increments the same way by default). Its residual is not
/// always smaller than that of u(t): where the plastic zone grows, the points it reaches carry
/// their overshoot of the yield stress as out-of-balance force, but the zone and the tangents
/// of the first iterate are close to the converged ones, which is what saves iterations
/// (measured on the bench cylinder: 4 iterations per plastic step instead of 5-6, even where
/// the residual norm of the extrapolated start was the larger). Returns the evaluation of the
/// start kept; rhs_ and the points hold it.
Equilibrium::Evaluation Equilibrium::predict(const State& c, State& trial,
                                             const Evaluation& at_start, double force_scale,
                                             bool& extrapolated) {
  const auto& dofs = m_.dofs();
  const double dt = trial.time - c.time;
  extrapolated = false;
  if (last_dt_ <= 0 || dt <= 0) return at_start;
  // A start already in equilibrium (the load does not change in this step) needs no
  // predictor, and the sign of its round-off out-of-balance force says nothing.
  if (std::sqrt(at_start.r2) <= m_.spec().solver.tolerance * force_scale) return at_start;
  double work = layout_.dot(rhs_, last_du_, own_free_);
  if (layout_.shared()) par::broadcast(std::span<double>(&work, 1));  // one decision for all ranks
  if (!(work > 0)) {
    log_.detail("  predictor: the load reverses (no work on the last increment); no extrapolation");
    return at_start;
  }
  const double scale = dt / last_dt_;
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) trial.u[i] += scale * last_du_[k];
  points_.begin_step(c, trial);  // the extrapolated start is the step's iteration 0
  Evaluation ev = evaluate(c, trial, false);
  extrapolated = true;
  ev.points.tangent_changed = ev.points.tangent_changed || at_start.points.tangent_changed;
  log_.detail(
      "  predictor: extrapolated start ({:.3g} of the last increment), residual {:.3e} "
      "(from the converged state {:.3e})",
      scale, std::sqrt(ev.r2), std::sqrt(at_start.r2));
  return ev;
}

/// The iteration's log line (and the contact's).
void Equilibrium::report(const StepOutcome& out) const {
  if (plastic_) {
    log_.detail(
        "  iteration {}: relative residual {:.3e}  Δσ {:.3e}  Δε {:.3e}  plastic "
        "points {}",
        out.iterations, out.residual, out.delta_sigma, out.delta_eps, out.plastic_points);
  } else {
    log_.detail("  iteration {}: relative residual {:.3e}", out.iterations, out.residual);
  }
  if (contact_.active()) {
    const ContactProgress& cp = contact_.progress();
    log_.detail("    contact: {} nodes{}{}, largest |gap| {:.2e} of the allowed", cp.in_contact,
                cp.set_changed ? ", set changed" : "", cp.kappa_raised ? ", κ raised" : "",
                cp.worst_gap);
  }
}

bool Equilibrium::converging_on(const StepOutcome& out) const {
  // solver.max_iterations: auto. A step that reaches the limit while its measures still fall
  // steadily goes on, up to twice the limit, where their rate over the last iterations says it
  // meets the tolerance before then; a step whose iteration stalls or oscillates stops at the
  // limit as before. Abaqus/Standard's time incrementation does the same at its limit I_C
  // (the logarithmic rate of convergence check: it continues while the residuals fall fast
  // enough to converge within the iterations left). Measured on the issue-16 cases:
  // variable-stiffness on the plastic indentation reached 50 iterations at t = 0.25 with a
  // residual of 1.6e-6 against 1e-6, still falling, and was cut back.
  constexpr int window = 10;
  const int limit = max_iterations_, cap = 2 * limit;
  const int k = static_cast<int>(distances_.size()) - 1;
  if (m_.spec().solver.max_iterations > 0 || out.iterations >= cap || k < window ||
      (contact_.active() && !contact_.progress().converged()))
    return false;
  const double first = distances_[k - window], worst = distances_[k];
  if (!(worst > 0 && first > worst && std::isfinite(first))) return false;
  const double rate = std::pow(worst / first, 1.0 / window);  // per iteration, < 1
  if (worst * std::pow(rate, cap - out.iterations) > 1) return false;
  if (out.iterations == limit)
    log_.detail(
        "  {} iterations (solver.max_iterations: auto) with the measures falling by {:.3g} "
        "per iteration: the step goes on, up to {}",
        limit, rate, cap);
  return true;
}

/// Every measure within the tolerance, after at least one solve.
bool Equilibrium::converged(const StepOutcome& out) const {
  const double tol = m_.spec().solver.tolerance;
  const bool measures_ok = !plastic_ || (out.delta_sigma <= tol && out.delta_eps <= tol);
  const bool contact_ok = !contact_.active() || contact_.progress().converged();
  return out.iterations >= 1 && out.residual <= tol && measures_ok && contact_ok;
}

/// The checks a converged iterate must pass before it is the answer of the step.
void Equilibrium::accept(const State& c, State& trial, double scale, StepOutcome& out) {
  const auto& spec = m_.spec().solver;
  // The reported residual is the true equilibrium defect F − F_int (γ only shifts the target).
  out.residual = scale > 0 ? equilibrium_defect(trial) / scale : 0.0;
  // Small strains: an equilibrium found with displacements of the order of the body is a
  // mechanism (a load at or above the plastic limit load), not an answer.
  if (plastic_ && !updated_) {
    double u_max = 0;
    for (int n = 0; n < m_.mesh().n_nodes(); ++n)
      u_max = std::max(u_max, Vec3(trial.u[3 * n], trial.u[3 * n + 1], trial.u[3 * n + 2]).norm());
    u_max = layout_.largest(u_max);
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
  if (extrapolate_) remember_increment(c, trial);
}

/// The next iterate: a new matrix when the scheme's rule or the contact asks for one, the
/// solve, the acceleration.
void Equilibrium::advance(const State& c, State& trial, const Evaluation& ev, int iteration,
                          double residual, double& previous_residual) {
  const auto& dofs = m_.dofs();
  const auto& spec = m_.spec().solver;
  const MatrixPolicy policy = scheme_->matrix_policy();
  // Under `geometry: updated` the matrix is that of the step's configuration, rebuilt at each
  // step's start, and for the schemes whose matrix follows the iterate (newton,
  // variable-stiffness) at every iteration: the iterate's deformation and stress enter it
  // (updated_matrix, element_matrix.cpp), also for elastic points.
  const bool new_elements =
      !factorized_ || (iteration == 0 && (matrix_changes_with_temperature_ || updated_)) ||
      (updated_ && policy == MatrixPolicy::per_iteration) ||
      (ev.points.tangent_changed &&
       (policy == MatrixPolicy::per_iteration ||
        (policy == MatrixPolicy::per_step && iteration <= first_iteration_ + 1)));
  // Whether this iterate made things worse than the one before. The residual doubled, or for
  // the initial-strain schemes the change of their iterated state (Δε^0, and the contact
  // nodes' c) that its evaluation asks for, in the norm Anderson's least squares minimizes,
  // grew tenfold. The residual is no merit function for them: a mixed iterate that settles
  // the slow plastic strains along Z raised it up to twentyfold for one iteration while their
  // change fell tenfold, and the iterations after it converged; dropping such iterates kept
  // the ball indentation's history at one column (t = 0.25 -> 0.5: 614 iterations; with the
  // change doubled as the criterion 305, tenfold 177, with no fallback at all 178). The
  // fallback is still what stops a mixed iterate that throws the points off their branch
  // (the multilinear cube below).
  const bool strains = mix_ && scheme_->iterates_initial_strain();
  double change = 0;
  if (strains && iteration > 0) change = strain_state_change(trial);
  const bool worse =
      strains ? iteration > 0 && change > 100 * last_change_ : residual > 2 * previous_residual;
  if (mix_ && mixed_last_ && worse) {
    // Safeguarded mixing: a mixed iterate that made things worse is dropped for the plain one
    // it replaced, and the history starts again there (as Peng et al., "Anderson
    // acceleration for geometry optimization and physics simulation", ACM TOG 37(4), 2018,
    // fall back to the plain step when the mixed one does not decrease their energy). The next
    // iteration evaluates it; nothing is solved in this one. Without it, a mixed λ0 that put
    // every point of a multilinear cube below its yield stress made the plain update return
    // to the step's start: a cycle of three iterations until the step failed.
    log_.detail(
        "  the mixed iterate {}: back to the plain one",
        strains ? "raised the change of the initial strains tenfold" : "doubled the residual");
    trial.u = plain_u_;
    trial.contact = plain_contact_;
    points_.restore_memory();
    if (strains) {  // the plain iterate's state, which its evaluation's change is measured from
      points_.initial_strains(lambda0_in_);
      if (contact_.active()) contact_.augmented_offsets(trial, contact_in_);
    }
    mixed_last_ = false;
    restart_next_ = true;  // the history starts again at the plain iterate
    return;
  }
  if (strains && iteration > 0) last_change_ = change;
  // Asked on every rank: on a distributed mesh the ranks agree on it (collective).
  const bool stale = contact_.matrix_stale(trial);
  const bool refactor = new_elements || stale;
  if (refactor) assemble_and_factorize(c, trial, new_elements);
  // An iterative solve need only reduce this iterate's residual to 0.1 % of the step's
  // tolerance, not to its own default (an inexact Newton method with a fixed forcing term,
  // after Eisenstat and Walker): the error it leaves is a thousandth of what convergence
  // allows, and the residual recomputed from the points still decides.
  if (residual > 0) system_.set_relative_tolerance(1e-3 * spec.tolerance / residual);
  auto t0 = Clock::now();
  system_.solve(rhs_, delta_);
  if (!options_checked_) {
    // PETSc ignores options it does not know: say so once it has read them (at set-up).
    options_checked_ = true;
    for (const auto& name : system_.unused_options())
      log_.warn(fmt::format(
          "PETSc option '{}' was not used (misspelt, or for a solver that is not in use)", name));
  }
  timings_.solve += seconds_since(t0);
  if (mix_) {
    // A new matrix is a new fixed-point map, and so is a new contact set or a raised κ; a step
    // that doubled the residual left the region where the history describes it: start the
    // history again from here.
    const bool contact_moved =
        contact_.active() && (contact_.progress().set_changed || contact_.progress().kappa_raised);
    const bool restart = iteration == 0 || refactor || contact_moved || restart_next_ || worse;
    restart_next_ = false;
    if (restart) anderson_.reset();
    previous_residual = residual;
    // The initial-strain schemes' displacement follows their Δε^0 only from the first solve
    // with the matrix on: the start of a step (u(t), the new load not yet applied) and the
    // iterate before a new matrix do not. Their plain update is the history's first entry.
    // After a restart the history holds nothing: the step is the plain one.
    mixed_last_ = !restart;
    if (mixed_last_) {
      plain_u_ = trial.u;
      for (int i = 0; i < dofs.n_dofs(); ++i)
        if (int k = dofs.eq[i]; k >= 0) plain_u_[i] += delta_[k];
      plain_contact_ = trial.contact;
      points_.save_memory();
    }
    if (scheme_->iterates_initial_strain() && restart) {
      points_.initial_strains(lambda0_in_);
      if (contact_.active()) contact_.augmented_offsets(trial, contact_in_);
    } else {
      mix(trial);
    }
  }
  // The first correction of a step carries its new load from u(t) (or the predictor's start):
  // the search serves the iterations after it, while the residual is above the tolerance (below
  // it the correction is round-off, and scaling it by the ratio of two round-off works made
  // the same case take 12 iterations serially and 11 on two ranks).
  if (line_search_ && iteration > 0 && residual > spec.tolerance) return line_search(c, trial);
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) trial.u[i] += delta_[k];
}

/// solver.line_search: the iterate u + s·δ, s from one secant step on g(s) = δ·r(u + s·δ), the
/// residual's work along the correction (Matthies and Strang, "The solution of nonlinear
/// finite element equations", Int. J. Numer. Meth. Engng 14, 1979; Crisfield, Non-linear
/// Finite Element Analysis of Solids and Structures, vol. 1, 1991, ch. 9). g(0) = δ·r(u) =
/// rᵀK⁻¹r > 0 with K positive definite; r(u + δ) costs one point pass. Where g(1) kept more
/// than a fifth of g(0) the correction fell short (the secant of variable-stiffness is stiffer
/// than the curve's tangent, so its corrections undershoot on a hardening curve), and the root
/// of the secant through g(0) and g(1) lengthens it, to at most 3δ; where g(1) reversed beyond
/// half of g(0) it overshot, and the root shortens it, to at least δ/5. Otherwise δ is taken
/// whole and the evaluation of u + δ is the next iterate's (with contact, once the contact has
/// been updated at it): the search then costs nothing. One secant step, not a search to a
/// tolerance: each further step would cost another point pass for less.
/// Measured (issue 16, findings 4 and 5; docs/schemes.md): variable-stiffness needs 20-35 %
/// fewer iterations and factorizations on the perfectly plastic cylinders (217 -> 142 at 81k
/// unknowns) and the plate-hole example, half as many on the force and pressure unloading
/// cases; the answers move within the tolerance. newton's ratio stays in the band on the
/// issue-16 cases (its iterates are those without the search, bit for bit), and leaves it where
/// its plastic iterates overshoot: the ball indentation on half its steps, which lifts the ball
/// out of the dent in one step (t = 1 -> 1.25), reversed the work (g(1)/g(0) = -1.32, s = 0.43)
/// and took 7 iterations; taken whole, the springback overshot, the node under the centre went
/// into the ball and out again seven times, and the step was cut back twice.
void Equilibrium::line_search(const State& c, State& trial) {
  const auto& dofs = m_.dofs();
  const auto move = [&](double s) {
    for (int i = 0; i < dofs.n_dofs(); ++i)
      if (int k = dofs.eq[i]; k >= 0) trial.u[i] = u_before_[i] + s * delta_[k];
  };
  const auto work = [&] { return layout_.dot(delta_, rhs_, own_free_); };
  u_before_ = trial.u;
  double g0 = work();
  // Every rank takes the same decisions (their sums may differ in the last bits): root's.
  if (layout_.shared()) par::broadcast(std::span<double>(&g0, 1));
  move(1.0);
  if (!(g0 > 0)) return;  // no descent direction of the energy: δ whole
  points_.save_memory();  // (Anderson's fallback keeps it too; it never mixes these schemes)
  Evaluation ev = evaluate(c, trial, false);
  const double ratio = work() / g0;
  double s = 1;
  if (ratio > 0.2)
    s = ratio < 2.0 / 3.0 ? 1 / (1 - ratio) : 3.0;
  else if (ratio < -0.5)
    s = std::max(0.2, 1 / (1 - ratio));
  if (layout_.shared()) par::broadcast(std::span<double>(&s, 1));
  if (s == 1) {
    // δ whole: this is the next iterate's evaluation, once the contact has been updated at it
    // (what evaluate(c, trial, true) does after the points; its residual then changes).
    if (contact_.active()) {
      update_contact_states(c, trial);
      ev.r2 = residual_vector(trial, &ev.r_loads2);
    }
    searched_ = std::move(ev);
    return;
  }
  points_.restore_memory();  // the matrices too: the next update compares with the solve's
  if (s != 1)
    log_.detail("  line search: the correction times {:.3f} (its work from {:.3e} to {:.3e})", s,
                g0, ratio * g0);
  move(s);
}

/// The initial-strain schemes: the points' plain update of Δε^0 and the contact nodes' c
/// (into lambda0_out_, contact_out_) against the state the iterate was evaluated with
/// (lambda0_in_, contact_in_), with the rows' weights of Anderson's least squares
/// (point_weights_, contact_weights_, the latter shared out over the ranks); returns the weighted
/// square of the change, over all ranks.
double Equilibrium::strain_state_change(const State& trial) {
  points_.initial_strains(lambda0_out_);
  points_.plastic_point_weights(point_weights_);
  double sum = 0;
  for (std::size_t j = 0; j < lambda0_out_.size(); ++j) {
    const double d = lambda0_out_[j] - lambda0_in_[j];
    sum += point_weights_[j] * d * d;
  }
  contact_out_.clear();
  if (contact_.active()) {
    contact_.augmented_offsets(trial, contact_out_, &contact_weights_);
    // With the whole mesh every rank holds every contact node: its rows, summed over the
    // ranks, count once. (A distributed mesh's contact weights are its owners' alone.)
    const double share = only_ ? 1.0 / par::size() : 1.0;
    for (std::size_t j = 0; j < contact_out_.size(); ++j) {
      contact_weights_[j] *= share;
      const double d = contact_out_[j] - contact_in_[j];
      sum += contact_weights_[j] * d * d;
    }
  }
  // The points are each rank's own.
  if (only_ || layout_.kind() == NodalLayout::Kind::distributed)
    par::sum_in_place(std::span<double>(&sum, 1));
  // Every rank takes the same decisions with it: root's figure.
  if (layout_.shared()) par::broadcast(std::span<double>(&sum, 1));
  return sum;
}

/// Anderson's mixing of this iteration: the plain correction delta_ (and, for the
/// initial-strain schemes, the points' plain update of Δε^0) replaced by the mixed one.
/// The initial-strain schemes iterate on Δε^0, and the displacement follows it: after one
/// solve with the scheme's fixed matrix, u + δ is the displacement of the plain update of Δε^0
/// exactly (the stress law is linear in Δε for fixed Δε^0), so the mixed displacement is the
/// same combination of those displacements as the mixed Δε^0 is of the plain updates. The
/// least squares then weighs only Δε^0 (by the points' volumes and moduli) and the contact's
/// c; the displacements weigh 0.
void Equilibrium::mix(State& trial) {
  const auto& dofs = m_.dofs();
  const bool strains = scheme_->iterates_initial_strain();
  const bool contact = strains && contact_.active();
  const std::size_t n_u = dofs.n_free;
  // (advance() gathered the points' and nodes' plain update and their weights)
  const std::size_t n_l = strains ? lambda0_out_.size() : 0;
  const std::size_t n_c = contact ? contact_out_.size() : 0;
  const std::size_t n = n_u + n_l + n_c;
  // The rows' weights: 1 for displacements iterated themselves, 0 for those that follow the
  // mixed state; volume·2G or G for Δε^0 and 1/κ for a contact node's c, so that each weighted
  // square is an energy.
  mix_weights_.assign(n, strains ? 0.0 : 1.0);
  if (strains) std::copy(point_weights_.begin(), point_weights_.end(), mix_weights_.begin() + n_u);
  // A distributed mesh: a ghost's rows are its owner's (weight 0 here).
  const bool distributed = layout_.kind() == NodalLayout::Kind::distributed;
  if (distributed) std::fill(mix_weights_.begin() + own_free_, mix_weights_.begin() + n_u, 0.0);
  for (std::size_t j = 0; j < n_c; ++j) mix_weights_[n_u + n_l + j] = contact_weights_[j];
  mix_x_.resize(n);
  mix_f_.resize(n);
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) mix_x_[k] = trial.u[i];
  std::copy(delta_.begin(), delta_.end(), mix_f_.begin());
  for (std::size_t j = 0; j < n_l; ++j) {
    mix_x_[n_u + j] = lambda0_in_[j];
    mix_f_[n_u + j] = lambda0_out_[j] - lambda0_in_[j];
  }
  for (std::size_t j = 0; j < n_c; ++j) {
    mix_x_[n_u + n_l + j] = contact_in_[j];
    mix_f_[n_u + n_l + j] = contact_out_[j] - contact_in_[j];
  }
  // The displacements are whole on every rank, or a distributed mesh's own rows on each; the
  // points are each rank's own.
  std::function<void(std::span<double>)> reduce;
  if ((strains && only_) || distributed) reduce = [](std::span<double> v) { par::sum_in_place(v); };
  anderson_.accelerate(mix_x_, mix_f_, mix_weights_, reduce);
  std::copy(mix_f_.begin(), mix_f_.begin() + n_u, delta_.begin());
  if (strains) {
    for (std::size_t j = 0; j < n_l; ++j) lambda0_in_[j] = mix_x_[n_u + j] + mix_f_[n_u + j];
    points_.set_initial_strains(lambda0_in_);
  }
  if (contact) {
    for (std::size_t j = 0; j < n_c; ++j)
      contact_in_[j] = mix_x_[n_u + n_l + j] + mix_f_[n_u + n_l + j];
    contact_.set_augmented_offsets(trial, contact_in_);
  }
}

/// rhs_ = target + F_contact − F_int on the free dofs for the evaluated iterate (the support's
/// forces computed here, into trial.f_contact); returns its squared norm, and in *loads2 (when
/// given) that of target − F_int, the residual without the supports.
double Equilibrium::residual_vector(State& trial, double* loads2) {
  const auto& dofs = m_.dofs();
  if (contact_.active()) {
    const auto t0 = Clock::now();
    contact_.forces(trial);
    timings_.contact += seconds_since(t0);
  }
  double r2 = 0, l2 = 0;
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) {
      const double loads = target_[i] - trial.f_int[i];
      rhs_[k] = loads + trial.f_contact[i];
      if (static_cast<std::size_t>(i) >= own_dofs_) continue;  // a ghost: its owner counts it
      r2 += rhs_[k] * rhs_[k];
      l2 += loads * loads;
    }
  if (layout_.kind() == NodalLayout::Kind::distributed) {
    double sums[2] = {r2, l2};
    par::sum_in_place(std::span<double>(sums));
    r2 = sums[0], l2 = sums[1];
  }
  if (loads2) *loads2 = l2;
  return r2;
}

double Equilibrium::equilibrium_defect(const State& s) const {
  double r = 0;
  for (std::size_t i = 0; i < own_dofs_; ++i)
    if (m_.dofs().eq[i] >= 0) {
      const double d = s.f_ext[i] + s.f_contact[i] - s.f_int[i];
      r += d * d;
    }
  return std::sqrt(layout_.total(r));
}

/// Keeps the free part of a converged step's displacement increment for the next predictor.
void Equilibrium::remember_increment(const State& c, const State& trial) {
  const auto& dofs = m_.dofs();
  last_du_.assign(dofs.n_free, 0.0);
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) last_du_[k] = trial.u[i] - c.u[i];
  last_dt_ = trial.time - c.time;
}

/// Assembles the matrix (the elements' part only when `new_elements` or when it was never
/// kept: a change of the contact alone starts from the elements' part of the last assembly)
/// and factorizes it.
void Equilibrium::assemble_and_factorize(const State& c, const State& trial, bool new_elements) {
  auto t0 = Clock::now();
  const State* start = updated_ ? &c : nullptr;
  if (new_elements || !contact_.active() || !system_.restore_cells()) {
    const auto& tangents = points_.tangents();
    assembled_tangents_ = tangents;
    system_.assemble_cells(
        [&](int e, CellBuffers& b) { element_matrix(m_, trial, tangents, x_, start, e, b); });
    if (contact_.active()) system_.keep_cells();
  }
  if (contact_.active())
    contact_.add_matrix(trial,
                        [&](int a, int b, const Mat3& block) { system_.add_block(a, b, block); });
  timings_.assembly += seconds_since(t0);
  factorize();
}

EquilibriumMemory Equilibrium::memory() const {
  EquilibriumMemory mem;
  mem.last_du = last_du_;
  mem.last_dt = last_dt_;
  mem.factorized = factorized_;
  if (factorized_) {
    mem.assembled_tangents = assembled_tangents_;
    mem.assembled_contact = contact_.assembled();
  }
  mem.tangents = points_.tangents();
  return mem;
}

void Equilibrium::resume(const State& c, EquilibriumMemory mem) {
  last_du_ = std::move(mem.last_du);
  last_dt_ = mem.last_dt;
  if (mem.factorized) {
    // The matrix the run had factorized when it wrote the checkpoint, from what it was made
    // of: the points' matrices then and the contact states then (which need not be the
    // converged ones: the matrix is kept while they change little). Under `geometry:
    // updated`, or with E or ν varying with the temperature, the next step assembles its own.
    points_.set_tangents(std::move(mem.assembled_tangents));
    State at = c;
    if (contact_.active()) at.contact = std::move(mem.assembled_contact);
    assemble_and_factorize(c, at, true);
  }
  points_.set_tangents(std::move(mem.tangents));
}

void Equilibrium::factorize() {
  const auto t0 = Clock::now();
  try {
    system_.factorize();
  } catch (const LinearSystemError& e) {
    if (negative_secant_cell_ < 0) throw;
    const Model::CellFacts cell = m_.cell_facts(negative_secant_cell_);
    // variable-stiffness with a negative slope: say why the matrix is indefinite (a plain
    // SolveError: the step failed, the supports are not to blame).
    throw SolveError(fmt::format(
        "{}: scheme 'variable-stiffness' has a negative slope of the curve of material "
        "'{}' at element {} (a softening curve makes its matrix indefinite); use newton or "
        "initial-stress",
        e.what(), m_.materials()[cell.material].spec->name, cell.tag));
  }
  if (m_.global_free() > 0) ++factorizations_;  // none where every dof is prescribed
  factorized_ = true;
  timings_.factorization += seconds_since(t0);
}

}  // namespace hencky
