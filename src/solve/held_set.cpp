#include "solve/held_set.hpp"

namespace hencky {

bool HeldPlasticSet::observe(const PointPassResult& r) {
  if (!holding_) return false;
  same_broken_ = r.holds_broken == last_broken_ ? same_broken_ + 1 : 1;
  last_broken_ = r.holds_broken;
  return r.holds_broken > 0;
}

bool HeldPlasticSet::update(int iteration, const PointPassResult& r, bool broken, bool converged,
                            PointPass& points, Log& log) {
  if (broken && (converged || same_broken_ >= settled_breaks)) {
    move(r.holds_broken, converged, points, log);
    return true;
  }
  if (iteration + 1 == hold_from && allowed_) {
    hold(r.plastic_points, points, log);
    return true;
  }
  return false;
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
/// SIAM J. Optim. 13, 2003; as Hüeber and Wohlmuth apply it to contact, see
/// Equilibrium::begin_again). The move does not wait for the answer: once the same number of
/// held points has stood beyond the yield stress in `settled_breaks` iterates in a row, these
/// are the points the answer would move, and the iteration of the held set only spends its
/// iterations on a map that is about to change (an inexact solve of each active set, as the
/// semismooth Newton view of the method allows). Measured on
/// tests/cli/inputs/issue16/indentation-unload, initial-strain, the step to t = 1: the count of
/// broken holds stood at 90 from iteration 35 on while the held set converged at iteration
/// 103, then at 13 from 127 to 175, and at 1 from 183 to 207. Moving after 3 iterates alike,
/// the issue-16 table's initial-strain runs: unload-all 312 -> 190 iterations
/// (initial-strain-stiffness 176 -> 110), the indentation 833 -> 380 and its two cut-backs gone
/// with the fixed-matrix schemes' flip limit (499 -> 330), indentation-half 923 -> 613 (622 ->
/// 444). With the flip limit of 6, after 2 iterates alike: 233, 653, 683; after 3: 190, 552,
/// 613; after 5: 199, 585, 646. After `max_moves` moves the points are set free again.
void HeldPlasticSet::hold(int plastic_points, PointPass& points, Log& log) {
  holding_ = true;
  moves_ = 0;
  const int held = points.hold_plastic_set();
  new_set();
  log.detail("  the plastic set is held from here ({} points plastic, {} in the last iterate)",
             held, plastic_points);
}

void HeldPlasticSet::move(int broken, bool converged, PointPass& points, Log& log) {
  new_set();
  if (++moves_ > max_moves) {
    points.free_plastic_set();
    holding_ = allowed_ = false;
    log.detail("  {} held points still beyond their yield stress after {} moves: every point free",
               broken, max_moves);
    return;
  }
  points.move_broken_holds();
  if (converged)
    log.detail(
        "  converged on the held set, but {} of its points lie beyond their yield stress: "
        "they change sides",
        broken);
  else
    log.detail(
        "  {} points of the held set lie beyond their yield stress in {} iterates in a row: "
        "they change sides",
        broken, settled_breaks);
}

}  // namespace hencky
