#pragma once
// The initial-strain schemes' held plastic set: an active-set iteration on the points' status
// (plastic or elastic) where Anderson's mixing alone cannot settle hundreds of points at their
// yield stress. held_set.cpp says why and what it was measured on.
#include "core/log.hpp"
#include "solve/point_pass.hpp"

namespace hencky {

class HeldPlasticSet {
 public:
  /// `enabled`: the scheme iterates initial strains (IterationPolicy::held_set).
  explicit HeldPlasticSet(bool enabled) : enabled_(enabled) {}
  /// A new step: every point free, the set may be held.
  void start_step() {
    holding_ = false;
    allowed_ = enabled_;
  }
  /// Observes an evaluated iterate; returns whether it broke holds: an answer of the held set
  /// whose stresses put some held points on the other side of their yield stress is not the
  /// step's (those points change sides, and the iteration goes on).
  bool observe(const PointPassResult& r);
  /// After the advance of `iteration` (whose iterate was observed: `broken`, `converged`):
  /// holds the set, moves the broken holds or frees every point. Returns true when the set
  /// changed: a new map (the mixing's history starts again).
  bool update(int iteration, const PointPassResult& r, bool broken, bool converged,
              PointPass& points, Log& log);

 private:
  void hold(int plastic_points, PointPass& points, Log& log);
  void move(int broken, bool converged, PointPass& points, Log& log);
  void new_set() {
    last_broken_ = -1;
    same_broken_ = 0;
  }

  // The iteration of the step from which the set is held, the iterates in a row with the same
  // number of broken holds after which these move, and the moves after which every point is
  // free again.
  static constexpr int hold_from = 20, max_moves = 10, settled_breaks = 3;
  bool enabled_;
  bool allowed_ = false, holding_ = false;  ///< may be held (this step), is held
  int moves_ = 0;                           ///< moves of this step's held set
  /// The number of broken holds of the last iterate (−1: none since the last hold or move), and
  /// in how many iterates in a row it was that number.
  int last_broken_ = -1, same_broken_ = 0;
};

}  // namespace hencky
