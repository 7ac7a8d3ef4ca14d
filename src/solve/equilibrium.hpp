#pragma once
// The equilibrium iteration of one load step (report section 2), stage by stage: the set-up and
// the evaluation of an iterate (iterate.hpp), the convergence test, and the advance to the next
// iterate (the matrix and its solve, step_matrix.hpp). hencky's additions to the report's
// iteration are strategies of their own, chosen once from the case (iteration_policy.hpp):
// newton's predictor, the line search, Anderson's mixing, the held plastic set, the iteration
// limit. The step control (step_control.cpp) decides which steps to take; this decides whether
// one converges.
#include <memory>
#include <string>

#include "core/log.hpp"
#include "linalg/linear_system.hpp"
#include "solve/held_set.hpp"
#include "solve/iterate.hpp"
#include "solve/iteration_policy.hpp"
#include "solve/line_search.hpp"
#include "solve/mixing.hpp"
#include "solve/predictor.hpp"
#include "solve/step_matrix.hpp"

namespace hencky {

/// How a step ended, or how far it got: the figures of its last iterate.
struct StepOutcome {
  int iterations = 0;
  double residual = 0;     ///< relative; at convergence the true equilibrium defect
  /// The residual relative to the step's own force scale alone (without the iterate's internal
  /// forces, which enter `residual`'s scale with contact and grow with a diverging iterate).
  double load_residual = 0;
  double delta_sigma = 0;  ///< the scheme's Δ^σ (0 without plasticity)
  double delta_eps = 0;
  int plastic_points = 0;
  /// geometry: updated: the last correction of the displacements relative to the step's
  /// increment, ‖δu‖/‖Δu‖ (0 otherwise, and before the first solve), and the one before it.
  double correction = 0, previous_correction = 0;
  /// The last iterate's largest σ̃/σ̃_y − 1 (its place once the step is accepted), and the
  /// points above σ̃_y·(1 + YieldExcess::slack).
  YieldExcess yield_excess;
  int points_above = 0;
  PointLargest point_von_mises;  ///< of the accepted state (accept)
  /// The step stopped because its residual diverged (IterationLimit::diverges): the step's best
  /// relative residual before it.
  bool diverged = false;
  double best_residual = 0;
};

class Equilibrium {
 public:
  /// `heat`: the heat analysis whose temperatures the steps take (temperature: {from: heat}),
  /// else none.
  Equilibrium(const Model& m, LinearSystem& system, Log& log, Timings& timings,
              HeatSolver* heat = nullptr);

  /// The initial state: undeformed, stress-free, at T_ref, no load.
  State initial_state() const;

  /// One step from `c` (committed at c.time) to time t1. Returns true when it converged and
  /// fills `trial`; `out` describes the last iterate either way (also when it throws).
  /// Throws SolveError (and LinearSystemError) when the step cannot go on.
  bool step(const State& c, double t1, State& trial, StepOutcome& out);

  int factorizations() const { return matrix_.factorizations(); }
  /// Tells `o` of every iterate (StepObserver::iterate_done); nullptr: nobody.
  void observe_iterates(StepObserver* o) { iterate_observer_ = o; }
  /// What the next step takes from the steps before it besides the State.
  EquilibriumMemory memory() const;
  /// Continues after a restart from `c` with the memory `mem` of the run that wrote it: the
  /// same matrix is assembled and factorized again. Collective.
  void resume(const State& c, EquilibriumMemory mem);
  /// Warnings after a converged step (curves left, temperatures outside tables). Collective.
  void check_curves(const State& s) const { iterate_.points().check_curves(s, log_); }
  /// Why the contact kept a failed step from converging (empty without contact).
  std::string contact_diagnosis() const { return iterate_.contact().diagnosis(); }
  /// The contact line of a converged step's log entry (empty without contact).
  std::string contact_summary(const State& s) const {
    return iterate_.contact().active() ? iterate_.contact().summary(s) : std::string();
  }

 private:
  /// The step's measures of an evaluated iterate into `out` (root's on every rank), logged;
  /// returns the force scale the residual is relative to.
  double measure(const State& trial, const Evaluation& ev, double f_norm, StepOutcome& out);
  void require_strain_form(const Evaluation& ev) const;
  Evaluation begin_again(const State& c, State& trial, const std::vector<double>& u_start);
  void report(const StepOutcome& out) const;
  bool converged(const StepOutcome& out) const;
  bool admissible(const StepOutcome& out) const;
  void accept(const State& c, State& trial, double scale, StepOutcome& out);
  bool released_pulling(const State& c, State& trial, Evaluation& ev, double scale,
                        StepOutcome& out);
  void advance(const State& c, State& trial, const Evaluation& ev, int iteration, double residual);

  const Model& m_;
  Log& log_;
  std::unique_ptr<Scheme> scheme_;
  IterationPolicy policy_;
  IterateEvaluator iterate_;
  StepMatrix matrix_;
  Predictor predictor_;
  LineSearch search_;
  Mixing mixing_;
  HeldPlasticSet held_;
  IterationLimit limit_;
  /// The iteration the step's points started from: 0, or 1 when it began again (begin_again).
  int first_iteration_ = 0;
  double model_size_ = 0;  ///< diagonal of the mesh's bounding box (plastic runs)
  StepObserver* iterate_observer_ = nullptr;
  int attempts_ = 0;  ///< steps attempted (IterateReport::attempt)
};

}  // namespace hencky
