#pragma once
// Which of hencky's additions to the report's iteration a run uses, decided once from the case
// and the scheme (choose_policy), and the iteration limit that follows from it. Each addition
// is a strategy of its own (solve/mixing.hpp, line_search.hpp, held_set.hpp, predictor.hpp, the
// contact's flip limit in contact_step.hpp); the measurements that justify each decision are
// written beside it in iteration_policy.cpp and in docs/schemes.md.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/log.hpp"
#include "solve/model.hpp"
#include "solve/schemes.hpp"

namespace hencky {

struct IterationPolicy {
  bool plastic = false;       ///< some material is plastic (the schemes' point laws run)
  bool mix = false;           ///< Anderson mixing of the iterates (solver.acceleration)
  int anderson_depth = 5;     ///< the mixing's history: 8 for the initial strains, else 5
  bool elastic_start = true;  ///< the first solve of a step that yields points is elastic
  int max_iterations = 50;    ///< solver.max_iterations resolved
  bool limit_given = false;   ///< solver.max_iterations is a number (no extension, IterationLimit)
  bool line_search = false;   ///< solver.line_search resolved
  bool extrapolate = false;   ///< newton's predictor (solver.predictor)
  bool held_set = false;      ///< the initial-strain schemes may hold their plastic set
  int max_flips = 6;          ///< contact flips a node may make in a step (ContactStep)
  /// formulation: report, none of the above: each step starts from the scheme's initial
  /// parameters (Scheme::evaluate_initial), the contact is (3.1)-(3.6) alone (no flip limit, no
  /// release of pulling nodes, no new start with the first iterate's contact set), and a step
  /// converges on the residual, Δ^σ and Δ^ε.
  bool report = false;
};

/// solver.max_iterations: auto, by the scheme's matrix policy.
int auto_max_iterations(MatrixPolicy policy);

/// The policy of the case's solver section for `scheme`.
IterationPolicy choose_policy(const Model& m, const Scheme& scheme);

/// The iteration limit: solver.max_iterations, and under `auto` the extension of a step whose
/// measures still fall steadily at the limit (converging_on).
class IterationLimit {
 public:
  explicit IterationLimit(const IterationPolicy& p)
      : limit_(p.max_iterations), given_(p.limit_given) {}
  void start_step() {
    distances_.clear();
    best_residual_ = INFINITY;
  }
  /// A step whose residual relative to its force scale (StepOutcome::load_residual), after its
  /// first solve, grows past `divergence_growth` times the best of the step and past 1 (the
  /// force scale itself) diverges: it stops at once, to be cut back. The largest growth over a
  /// step's best in converging runs: 8.9e3 over 105 runs of the CLI suite and the issue-16 table
  /// (the coarse cantilever-hook's first newton iterates under `updated`: 80.6 after 9.1e-3;
  /// without contact this residual is the logged one), 2.3e3 over 22 runs with contact measured
  /// on this residual itself (the issue-16 contact cases with five schemes, the ball
  /// indentation); a diverging iteration passes 1e6 within a few iterates.
  static constexpr double divergence_growth = 1e6;
  bool diverges(int iteration, double residual) {
    if (iteration < 1) return false;
    best_residual_ = std::min(best_residual_, residual);
    return residual > 1 && residual > divergence_growth * best_residual_;
  }
  double best_residual() const { return best_residual_; }
  /// Records an iterate's worst measure over the tolerance.
  void record(double worst) { distances_.push_back(worst); }
  /// Whether the step stops at `iteration` (at or past the limit and not converging on).
  /// `contact_converged`: no contact, or its last update converged. Logs an extension.
  bool reached(int iteration, bool contact_converged, Log& log) const;

 private:
  int limit_;
  bool given_;
  std::vector<double> distances_;  ///< the step's iterates' worst measure over the tolerance
  double best_residual_ = INFINITY;  ///< the step's smallest relative residual after a solve
};

}  // namespace hencky
