#pragma once
// solver.line_search: one secant step on the residual's work along a correction, for the
// schemes whose matrix follows the iterate (newton, variable-stiffness).
#include <optional>
#include <utility>
#include <vector>

#include "core/log.hpp"
#include "solve/iterate.hpp"

namespace hencky {

class LineSearch {
 public:
  explicit LineSearch(bool enabled) : enabled_(enabled) {}
  /// Whether the correction of `iteration` is searched: the first correction of a step carries
  /// its new load from u(t) (or the predictor's start), and the search serves the iterations
  /// after it, while the residual is above the tolerance (below it the correction is
  /// round-off, and scaling it by the ratio of two round-off works made the same case take 12
  /// iterations serially and 11 on two ranks).
  bool applies(int iteration, double residual, double tolerance) const {
    return enabled_ && iteration > 0 && residual > tolerance;
  }
  /// Moves trial.u along `delta` by the searched length (the residual at trial.u is in
  /// iterate.rhs()).
  void search(const State& c, State& trial, const std::vector<double>& delta,
              IterateEvaluator& iterate, Log& log);
  /// The evaluation of the last searched iterate when the search took δ whole (it is the next
  /// iterate's), else none; taken once.
  std::optional<Evaluation> take() { return std::exchange(searched_, std::nullopt); }
  void start_step() { searched_.reset(); }

 private:
  bool enabled_;
  std::optional<Evaluation> searched_;
  std::vector<double> u_before_;
};

}  // namespace hencky
