#pragma once
// newton's predictor (solver.predictor: extrapolate): the start of a step moved along the last
// converged increment when the new load keeps its direction.
#include <vector>

#include "core/log.hpp"
#include "solve/iterate.hpp"

namespace hencky {

class Predictor {
 public:
  explicit Predictor(bool enabled) : enabled_(enabled) {}
  bool enabled() const { return enabled_; }
  /// The step starts from the converged state (evaluated: `at_start`, its residual in
  /// iterate.rhs()). Returns the evaluation of the start kept; `extrapolated` says whether it
  /// moved.
  Evaluation predict(const State& c, State& trial, const Evaluation& at_start, double force_scale,
                     bool& extrapolated, IterateEvaluator& iterate, Log& log) const;
  /// Keeps the free part of a converged step's displacement increment for the next step.
  void remember(const Model& m, const State& c, const State& trial);
  /// The last converged increment of the free unknowns and its Δt (a restart's memory).
  const std::vector<double>& last_du() const { return last_du_; }
  double last_dt() const { return last_dt_; }
  void resume(std::vector<double> du, double dt) {
    last_du_ = std::move(du);
    last_dt_ = dt;
  }

 private:
  bool enabled_;
  std::vector<double> last_du_;
  double last_dt_ = 0;
};

}  // namespace hencky
