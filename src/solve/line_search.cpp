#include "solve/line_search.hpp"

#include <algorithm>

#include "parallel/mpi.hpp"

namespace hencky {

/// The iterate u + s·δ, s from one secant step on g(s) = δ·r(u + s·δ), the residual's work
/// along the correction (Matthies and Strang, "The solution of nonlinear finite element
/// equations", Int. J. Numer. Meth. Engng 14, 1979; Crisfield, Non-linear Finite Element
/// Analysis of Solids and Structures, vol. 1, 1991, ch. 9). g(0) = δ·r(u) = rᵀK⁻¹r > 0 with K
/// positive definite; r(u + δ) costs one point pass. Where g(1) kept more than a fifth of g(0)
/// the correction fell short (the secant of variable-stiffness is stiffer than the curve's
/// tangent, so its corrections undershoot on a hardening curve), and the root of the secant
/// through g(0) and g(1) lengthens it, to at most 3δ; where g(1) reversed beyond half of g(0)
/// it overshot, and the root shortens it, to at least δ/5. Otherwise δ is taken whole and the
/// evaluation of u + δ is the next iterate's (with contact, once the contact has been updated
/// at it): the search then costs nothing. One secant step, not a search to a tolerance: each
/// further step would cost another point pass for less.
/// Measured (issue 16, findings 4 and 5; docs/schemes.md): variable-stiffness needs 20-35 %
/// fewer iterations and factorizations on the perfectly plastic cylinders (217 -> 142 at 81k
/// unknowns) and the plate-hole example, half as many on the force and pressure unloading
/// cases; the answers move within the tolerance. newton's ratio stays in the band on the
/// issue-16 cases (its iterates are those without the search, bit for bit), and leaves it where
/// its plastic iterates overshoot: the ball indentation on half its steps, which lifts the ball
/// out of the dent in one step (t = 1 -> 1.25), reversed the work (g(1)/g(0) = -1.32, s = 0.43)
/// and took 7 iterations; taken whole, the springback overshot, the node under the centre went
/// into the ball and out again seven times, and the step was cut back twice.
void LineSearch::search(const State& c, State& trial, const std::vector<double>& delta,
                        IterateEvaluator& iterate, Log& log) {
  const auto& dofs = iterate.model().dofs();
  const NodalLayout& layout = iterate.model().layout();
  const auto move = [&](double s) {
    for (int i = 0; i < dofs.n_dofs(); ++i)
      if (int k = dofs.eq[i]; k >= 0) trial.u[i] = u_before_[i] + s * delta[k];
  };
  const auto work = [&] { return layout.dot(delta, iterate.rhs(), iterate.own_free()); };
  u_before_ = trial.u;
  double g0 = work();
  // Every rank takes the same decisions (their sums may differ in the last bits): root's.
  if (layout.shared()) par::broadcast(std::span<double>(&g0, 1));
  move(1.0);
  if (!(g0 > 0)) return;           // no descent direction of the energy: δ whole
  iterate.points().save_memory();  // (Anderson's fallback keeps it too; it never mixes these)
  Evaluation ev = iterate.evaluate(c, trial, false);
  const double ratio = work() / g0;
  double s = 1;
  if (ratio > 0.2)
    s = ratio < 2.0 / 3.0 ? 1 / (1 - ratio) : 3.0;
  else if (ratio < -0.5)
    s = std::max(0.2, 1 / (1 - ratio));
  if (layout.shared()) par::broadcast(std::span<double>(&s, 1));
  if (s == 1) {
    // δ whole: this is the next iterate's evaluation, once the contact has been updated at it
    // (what evaluate(c, trial, true) does after the points; its residual then changes).
    if (iterate.contact().active()) iterate.update_contact(c, trial, ev);
    searched_ = std::move(ev);
    return;
  }
  iterate.points().restore_memory();  // the matrices too: the next update compares with the solve's
  log.detail("  line search: the correction times {:.3f} (its work from {:.3e} to {:.3e})", s, g0,
             ratio * g0);
  move(s);
}

}  // namespace hencky
