#include "solve/iteration_policy.hpp"

#include <cmath>
#include <limits>

#include "solve/contact_step.hpp"

namespace hencky {

/// An iteration of a fixed-matrix scheme is a back-substitution and a stress evaluation, tens
/// of times cheaper than newton's factorization (31 + 19 ms against 0.9 s at 81k unknowns,
/// docs/schemes.md), and it converges linearly: while yield spreads the mixed iterations
/// needed up to 60 a step (initial-stress, the plate with a hole) and 185 (initial-strain, the
/// same). With 50 for every scheme, the issue-16 cases cut back steps that were converging
/// (initial-stress on unload-all failed at 50 iterations with a residual of 3e-7 against 1e-6;
/// both initial-stress schemes were cut back on unload-all and the indentation); with 200 none
/// is (unload-all 182 -> 123 iterations in all, no cut-back, as the cut-back attempts no
/// longer count).
int auto_max_iterations(MatrixPolicy policy) {
  return policy == MatrixPolicy::per_iteration ? 50 : 200;
}

IterationPolicy choose_policy(const Model& m, const Scheme& scheme) {
  const SolverSpec& spec = m.spec().solver;
  IterationPolicy p;
  p.plastic = m.has_plasticity();
  const bool strains = scheme.iterates_initial_strain();
  // The flips a contact node may make in a step before the set is called oscillating
  // (ContactStep::update): 6 for the schemes whose matrix follows the iterate, scaled with
  // the scheme's automatic iteration limit: 24 for the fixed-matrix schemes, which iterate
  // linearly, and a node at the edge of the contact follows their unsettled plastic
  // strains for longer before it settles. Measured on
  // tests/cli/inputs/issue16/indentation-unload, initial-strain: a node at the edge flipped 7
  // times in the first 22 iterations of the step to t = 1 (Δε measure 3-16), and the step and
  // its first cut-back were cut back again; with no limit at all the set settled by iteration
  // 25 in every step.
  p.max_flips = ContactStep::default_max_flips * auto_max_iterations(scheme.matrix_policy()) /
                auto_max_iterations(MatrixPolicy::per_iteration);
  // The history's depth: the initial strains' state (Δε^0 along the trial's Z, the held
  // plastic set, with contact the nodes' c) is further from linear than the initial
  // stresses' displacements, and a longer history fits more of it. Measured with depth
  // 5 -> 8 -> 10 on the issue-16 table: the indentation 1742 iterations and 4 cut-backs ->
  // 833 and 2 -> 831 and 2 (initial-strain), 587 -> 499 -> 527 (initial-strain-stiffness);
  // unload-all 427 -> 312 -> 331 and 212 -> 176 -> 201; the multilinear cube 126 -> 136 ->
  // 143 and 55 -> 59 -> 61; the others within two iterations.
  p.anderson_depth = strains ? 8 : 5;
  // Not with contact: extrapolating a long step after short ones pushes the nodes near the
  // contact far into the surfaces (8 increments deep on a plastic indentation, where the
  // step then failed; from the converged state it took 10 iterations).
  p.extrapolate =
      p.plastic && scheme.kind() == SchemeKind::newton && spec.extrapolate && m.contacts().empty();
  // solver.acceleration: auto mixes wherever the scheme's iteration is a fixed map (the reader
  // refuses `anderson` elsewhere).
  using A = SolverSpec::Acceleration;
  const A a = spec.acceleration;
  // With a relaxation of their own the initial-strain schemes keep the report's plain
  // iteration unless `anderson` is asked for: a given ω far from auto's makes the relaxed
  // initial strain a poor secant history (measured: a restrained heated bar with ω = 0.03
  // converges plain and cycles mixed).
  const bool given_omega = strains && spec.relaxation > 0;
  // Without plasticity every scheme is the same linear solve per step: nothing to mix (with
  // contact the mixing only disturbed the augmented iteration: 56 iterations instead of 42 on
  // the elastic ball-indentation example).
  p.mix = p.plastic &&
          (a == A::anderson || (a == A::automatic && scheme.allows_acceleration() && !given_omega));
  // For the same reason no elastic start with a given ω: the plain iteration's first update of
  // λ0 comes from the overshoot of u(t) (measured: a uniaxial load-unload-reload at ω = 0.01,
  // initial-strain-stiffness, took 677 iterations and failed on reloading with the elastic
  // start, 0.99 per iteration from the elastic iterate; 37 iterations without).
  p.elastic_start = !given_omega;
  p.limit_given = spec.max_iterations > 0;
  p.max_iterations =
      p.limit_given ? spec.max_iterations : auto_max_iterations(scheme.matrix_policy());
  // solver.line_search: the schemes whose matrix follows the iterate, variable-stiffness and
  // newton; the fixed-matrix schemes have Anderson's mixing instead.
  p.line_search =
      p.plastic && spec.line_search && scheme.matrix_policy() == MatrixPolicy::per_iteration;
  p.held_set = p.plastic && strains;
  if (scheme.has_initial_evaluation()) {
    // The report's iteration (the reader refused the settings that would add to it).
    p.report = true;
    p.mix = p.elastic_start = p.line_search = p.extrapolate = p.held_set = false;
    p.limit_given = true;  // no extension of the limit either
    p.max_flips = std::numeric_limits<int>::max();
  }
  return p;
}

bool IterationLimit::reached(int iteration, bool contact_converged, Log& log) const {
  if (iteration < limit_) return false;
  // solver.max_iterations: auto. A step that reaches the limit while its measures still fall
  // steadily goes on, up to twice the limit, where their rate over the last iterations says it
  // meets the tolerance before then; a step whose iteration stalls or oscillates stops at the
  // limit as before. Abaqus/Standard's time incrementation does the same at its limit I_C
  // (the logarithmic rate of convergence check: it continues while the residuals fall fast
  // enough to converge within the iterations left). Measured on the issue-16 cases:
  // variable-stiffness on the plastic indentation reached 50 iterations at t = 0.25 with a
  // residual of 1.6e-6 against 1e-6, still falling, and was cut back.
  constexpr int window = 10;
  const int cap = 2 * limit_;
  const int k = static_cast<int>(distances_.size()) - 1;
  if (given_ || iteration >= cap || k < window || !contact_converged) return true;
  const double first = distances_[k - window], worst = distances_[k];
  if (!(worst > 0 && first > worst && std::isfinite(first))) return true;
  const double rate = std::pow(worst / first, 1.0 / window);  // per iteration, < 1
  if (worst * std::pow(rate, cap - iteration) > 1) return true;
  if (iteration == limit_)
    log.detail(
        "  {} iterations (solver.max_iterations: auto) with the measures falling by {:.3g} "
        "per iteration: the step goes on, up to {}",
        limit_, rate, cap);
  return false;
}

}  // namespace hencky
