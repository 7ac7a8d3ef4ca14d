#include "solve/predictor.hpp"

#include <cmath>

#include "parallel/mpi.hpp"

namespace hencky {

/// When the last step moved the free nodes by Δu_n and the new step's out-of-balance force
/// does positive work on Δu_n (the load keeps its direction: not a reversal), the start moves
/// on to u(t) + (Δt/Δt_n)·Δu_n, the linear extrapolation of the path (Abaqus/Standard starts
/// its increments the same way by default). Its residual is not always smaller than that of
/// u(t): where the plastic zone grows, the points it reaches carry their overshoot of the yield
/// stress as out-of-balance force, but the zone and the tangents of the first iterate are
/// close to the converged ones, which is what saves iterations (measured on the bench
/// cylinder: 4 iterations per plastic step instead of 5-6, even where the residual norm of the
/// extrapolated start was the larger).
Evaluation Predictor::predict(const State& c, State& trial, const Evaluation& at_start,
                              double force_scale, bool& extrapolated, IterateEvaluator& iterate,
                              Log& log) const {
  const Model& m = iterate.model();
  const auto& dofs = m.dofs();
  const NodalLayout& layout = m.layout();
  const double dt = trial.time - c.time;
  extrapolated = false;
  if (last_dt_ <= 0 || dt <= 0) return at_start;
  // A start already in equilibrium (the load does not change in this step) needs no
  // predictor, and the sign of its round-off out-of-balance force says nothing.
  if (std::sqrt(at_start.r2) <= m.spec().solver.tolerance * force_scale) return at_start;
  double work = layout.dot(iterate.rhs(), last_du_, iterate.own_free());
  if (layout.shared()) par::broadcast(std::span<double>(&work, 1));  // one decision for all ranks
  if (!(work > 0)) {
    log.detail("  predictor: the load reverses (no work on the last increment); no extrapolation");
    return at_start;
  }
  const double scale = dt / last_dt_;
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) trial.u[i] += scale * last_du_[k];
  iterate.points().begin_step(c, trial);  // the extrapolated start is the step's iteration 0
  Evaluation ev = iterate.evaluate(c, trial, false);
  extrapolated = true;
  ev.points.tangent_changed = ev.points.tangent_changed || at_start.points.tangent_changed;
  log.detail(
      "  predictor: extrapolated start ({:.3g} of the last increment), residual {:.3e} "
      "(from the converged state {:.3e})",
      scale, std::sqrt(ev.r2), std::sqrt(at_start.r2));
  return ev;
}

void Predictor::remember(const Model& m, const State& c, const State& trial) {
  const auto& dofs = m.dofs();
  last_du_.assign(dofs.n_free, 0.0);
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) last_du_[k] = trial.u[i] - c.u[i];
  last_dt_ = trial.time - c.time;
}

}  // namespace hencky
