#pragma once
// solver.acceleration: Anderson's mixing of the fixed-matrix schemes' iterates (anderson.hpp),
// with its safeguard (a mixed iterate that made things worse is dropped for the plain one).
// The initial-stress schemes mix the displacements; the initial-strain schemes mix their
// initial strains Δε^0 and the contact nodes' augmented state, which the displacements follow.
#include <vector>

#include "core/log.hpp"
#include "solve/anderson.hpp"
#include "solve/iterate.hpp"

namespace hencky {

class Mixing {
 public:
  /// `enabled`: IterationPolicy::mix; `strains`: the scheme iterates initial strains;
  /// `only`: this rank's cells (nullptr: every cell).
  Mixing(bool enabled, int depth, bool strains, IterateEvaluator& iterate,
         const std::vector<char>* only);
  /// A new step: no history, nothing to fall back to.
  void start_step();
  /// A new map (a new held set, contact set or start): the history starts again at the next
  /// solve, and no fallback across it.
  void new_map() {
    restart_next_ = true;
    mixed_last_ = false;
  }
  /// Before the solve of `iteration` (relative `residual`): true when the last mixed iterate
  /// made things worse and trial is now the plain one it replaced (nothing is solved in this
  /// iteration: the next evaluates it).
  bool fell_back(State& trial, int iteration, double residual, Log& log);
  /// After the solve: `delta` (the plain correction) replaced by the mixed one, and the
  /// points' Δε^0 (and the contact's state) by the mixed state. `refactored`: the matrix
  /// changed for this solve (a new map).
  void mix_correction(State& trial, std::vector<double>& delta, int iteration, double residual,
                      bool refactored);

 private:
  /// A block of the mixed state beside the displacements: the state the iterate was evaluated
  /// with, the plain update of it, and the rows' weights.
  struct Block {
    std::vector<double> in, out, weights;
  };
  double strain_state_change(const State& trial);
  void mix(State& trial, std::vector<double>& delta);

  IterateEvaluator& iterate_;
  const std::vector<char>* only_;
  bool enabled_, strains_;
  Anderson anderson_;
  std::vector<double> rows_x_, rows_f_, rows_w_;  ///< the iterate, its correction, the weights
  Block points_, contact_;  ///< Δε^0 at the points, the contact nodes' c (strains_ only)
  // The initial-strain schemes: the weighted square of the change of their state that the last
  // iterate kept asked for (strain_state_change), what the safeguard compares the next with;
  // the other schemes: the residual of the last mixed iteration.
  double last_change_ = 0, previous_residual_ = 0;
  bool worse_ = false;  ///< the iterate of this iteration made things worse (fell_back)
  // The plain iterate the last mixed one replaced (its displacements, contact and points'
  // memory), taken instead when the mixed one made things worse.
  bool mixed_last_ = false, restart_next_ = false;
  std::vector<double> plain_u_;
  std::vector<std::vector<ContactNode>> plain_contact_;
};

}  // namespace hencky
