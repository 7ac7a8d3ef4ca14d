// The equilibrium iteration's two rules for rigid contact (equilibrium.hpp): a converged
// iterate whose surface pulls on a node releases it, and a step whose first iterate released
// nodes in contact and made points flow begins again. Neither is the report's (3.1)-(3.6):
// formulation: report has neither.
#include <fmt/format.h>

#include "parallel/mpi.hpp"
#include "solve/equilibrium.hpp"

namespace hencky {

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
  if (!iterate_.contact().active() || policy_.report) return false;
  double limit = m_.spec().solver.tolerance * scale;
  if (m_.layout().shared()) par::broadcast(std::span<double>(&limit, 1));  // every rank alike
  const int n = iterate_.contact().release_pulling(c, trial, limit);
  if (n == 0) return false;
  log_.detail("  converged, but the surface pulls on {} nodes in contact: released", n);
  // The residual without the released nodes' forces: what the next solve corrects (and what
  // its iterative tolerance and the line search's test are taken from).
  ev.r2 = iterate_.residual_vector(trial, &ev.r_loads2);
  out.residual = std::sqrt(ev.r2) / scale;
  mixing_.new_map();  // a new contact set: a new map for the mixing, no fallback across it
  return true;
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
Evaluation Equilibrium::begin_again(const State& c, State& trial,
                                    const std::vector<double>& u_start) {
  log_.detail(
      "  the first iterate released {} nodes in contact at t: the step begins again "
      "from u(t) with its contact set",
      iterate_.contact().progress().released);
  trial.u = u_start;
  iterate_.points().begin_step(c, trial);  // the points' memory of the step starts again
  // The solve from u(t) is the elastic one, as at the start of a step (step()). Measured:
  // with the start-of-step tangent instead, initial-stress-stiffness sprang the plastic
  // cylinder of VerifyContactPlastic into the roller (gaps 1e6 times the allowed one) and its
  // first unloading step failed after three cut-backs; with the elastic matrix it took 6
  // iterations (13 before this rule).
  mixing_.new_map();
  // The `-stiffness` schemes' start slopes are decided by the first iterates from here on
  // (start_slope_on_unloading), and their matrix may change with them. (Measured: the ball
  // indentation's first unloading step, initial-strain-stiffness, began again at iteration 1;
  // its flowing points found themselves unloading at iteration 2, the point law switched to 3G
  // while the matrix kept the loading slope, and the step diverged through five cut-backs.)
  first_iteration_ = 1;
  return iterate_.evaluate(c, trial, false,
                           policy_.elastic_start ? PointMode::elastic : PointMode::law);
}

}  // namespace hencky
