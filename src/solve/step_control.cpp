// Step control: which steps to take (the case's times, one at a time), cut-back of a step that
// fails, the log line and the observer of every converged step. Whether a step converges is
// the equilibrium iteration's business (equilibrium.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <deque>
#include <optional>

#include "core/interrupt.hpp"
#include "core/timer.hpp"
#include "parallel/mpi.hpp"
#include "solve/analysis.hpp"
#include "solve/driver.hpp"
#include "solve/equilibrium.hpp"
#include "solve/recovery.hpp"

namespace hencky {
namespace {

/// Targets still to reach, each with its cut-back depth: a step that fails is replaced by two
/// half steps one level deeper, down to `cutback` levels; the run then stops (status 2). The
/// case's step times are taken one at a time (a case may have a million steps): the queue
/// holds the current one and the cut-back targets before it.
class StepTargets {
 public:
  /// The case's times after `after` (0 at the start; a restart's time). `pending`: the targets
  /// a checkpoint had queued (RunMemory::pending); taken as they are when the case time they
  /// lead to is still one of the case's times (the same case: the run goes on as it would
  /// have), else the case's times after `after` are taken from a fresh start.
  StepTargets(const StepTimes& times, double after, const std::vector<StepTarget>& pending)
      : times_(times) {
    if (!pending.empty()) {
      const std::size_t k = first_after(pending.back().time, false);
      if (k < times_.size() && times_[k] == pending.back().time && pending.front().time > after) {
        queue_.assign(pending.begin(), pending.end());
        next_ = k + 1;
        return;
      }
    }
    next_ = first_after(after, true);
    take_next();
  }
  bool empty() const { return queue_.empty(); }
  double time() const { return queue_.front().time; }
  int depth() const { return queue_.front().depth; }
  /// The front target is reached: on to the next.
  void reached() {
    queue_.pop_front();
    take_next();
  }
  /// A target at `mid`, half way to the front one, before it; both one level deeper.
  void cut_back(double mid) {
    queue_.front().depth += 1;
    queue_.push_front({mid, queue_.front().depth});
  }
  std::vector<StepTarget> pending() const { return {queue_.begin(), queue_.end()}; }

 private:
  /// The index of the first case time above t (strictly: `strict`), else at or above it.
  std::size_t first_after(double t, bool strict) const {
    std::size_t lo = 0, hi = times_.size();
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (strict ? times_[mid] <= t : times_[mid] < t)
        lo = mid + 1;
      else
        hi = mid;
    }
    return lo;
  }
  void take_next() {
    if (queue_.empty() && next_ < times_.size()) queue_.push_back({times_[next_++], 0});
  }
  const StepTimes& times_;
  std::size_t next_ = 0;
  std::deque<StepTarget> queue_;
};

/// One attempt at the step to t1: true when it converged; `why` says why not. Input errors
/// found by the attempt (options PETSc cannot use, a body not held) are thrown as such.
bool attempt(const Model& model, Equilibrium& eq, const State& committed, double t1, State& trial,
             bool first_step, StepOutcome& out, std::string& why) {
  try {
    if (eq.step(committed, t1, trial, out)) return true;
    why = out.diverged
              ? fmt::format("the iteration diverges: the residual grew to {:.3e} of the step's "
                            "force scale in iteration {}, more than {:g} times its best in the "
                            "step ({:.3e})",
                            out.load_residual, out.iterations, IterationLimit::divergence_growth,
                            out.best_residual)
              : fmt::format("no convergence in {} iterations (relative residual {:.3e})",
                            out.iterations, out.residual);
    if (out.points_above > 0)
      why += fmt::format("; {} points of the last iterate lie above their yield stress, by up to "
                         "{:.3g}",
                         out.points_above, out.yield_excess.value);
    if (const std::string c = eq.contact_diagnosis(); !c.empty()) why += "; " + c;
  } catch (const SolverOptionsError& e) {
    throw InputError(SourceLocation{model.spec().file.string(), 0, 0, "solver.petsc_options"},
                     std::string(e.what()) +
                         ": PETSc cannot set the solver up with the options given "
                         "(solver.petsc_options, --petsc or PETSC_OPTIONS)");
  } catch (const LinearSystemError& e) {
    // The first solve of the analysis: the matrix of the elastic body itself cannot be
    // solved, the supports do not hold it.
    if (first_step && out.iterations == 0)
      throw InputError(SourceLocation{model.spec().file.string(), 0, 0, "boundary"},
                       std::string(e.what()) +
                           ": the body is not held against rigid-body motion (translations "
                           "and rotations); check the displacement conditions");
    why = e.what();
  } catch (const SolveError& e) {
    why = e.what();
  }
  return false;
}

/// The log lines of a converged step.
void log_step(const Model& model, const Equilibrium& eq, const StepReport& report,
              const State& committed, Log& log) {
  if (model.spec().heat.only) {  // nothing mechanical was solved
    const auto [lo, hi] =
        std::minmax_element(committed.nodal_temperature.begin(), committed.nodal_temperature.end());
    log.info("step {:4d}  t = {:<10.6g} temperatures {:.6g} .. {:.6g}", report.step, report.time,
             *lo, *hi);
  } else if (model.has_plasticity()) {
    log.info("step {:4d}  t = {:<10.6g} iterations {:3d}  residual {:.2e}  plastic points {}",
             report.step, report.time, report.iterations, report.residual, report.plastic_points);
    eq.check_curves(committed);
  } else {
    log.info("step {:4d}  t = {:<10.6g} iterations {:3d}  residual {:.2e}", report.step,
             report.time, report.iterations, report.residual);
  }
  if (const std::string line = eq.contact_summary(committed); !line.empty())
    log.info("           {}", line);
}

/// One run of the step loop: the committed and the trial state, the result's counts, and the
/// checkpoint of a converged step not written yet. run() takes the case's targets one at a time.
class StepLoop {
 public:
  /// Starts from the restart of `options` (its state, the heat analysis's and the iteration's
  /// memory, its counts), else from the equilibrium's initial state.
  StepLoop(const Model& model, Equilibrium& eq, HeatSolver* heat, Log& log, Timings& timings,
           StepObserver& observer, const RunOptions& options)
      : model_(model),
        eq_(eq),
        heat_(heat),
        log_(log),
        timings_(timings),
        observer_(observer),
        sink_(options.checkpoints),
        resume_(options.resume ? &options.resume->run : nullptr) {
    if (resume_) {
      committed_ = options.resume->committed;
      if (heat_ && resume_->heat) heat_->resume(*resume_->heat);
      eq_.resume(committed_, resume_->equilibrium);
      // The restart's factorization of the matrix the run had: in the summary's count, not in
      // the next step's (whose history row is then the uninterrupted run's).
      factorizations_before_ = eq_.factorizations();
      result_.steps = resume_->steps;
      result_.iterations = resume_->iterations;
      earlier_factorizations_ = resume_->factorizations;
    } else {
      committed_ = eq_.initial_state();
    }
    trial_ = committed_;
  }

  AnalysisResult run() {
    StepTargets targets(model_.spec().solver.times, committed_.time,
                        resume_ ? resume_->pending : std::vector<StepTarget>());
    while (!targets.empty())
      if (std::optional<AnalysisResult> stopped = take_step(targets)) return *stopped;
    return result_;
  }

 private:
  /// The step to the front target: attempted, cut back when it fails, committed, its outputs
  /// written. The result when the run stops there.
  std::optional<AnalysisResult> take_step(StepTargets& targets) {
    const double t1 = targets.time();
    const int depth = targets.depth();
    StepOutcome out;
    std::string why;
    bool ok = false;
    try {
      if (par::any(interrupt_requested()))
        throw Interrupted(fmt::format("interrupted before the step to t = {:g}", t1));
      ok = attempt(model_, eq_, committed_, t1, trial_, result_.steps == 0, out, why);
    } catch (const HeatDivergence& e) {  // the heat analysis cut its own steps back already
      return stop(AnalysisStatus::not_converged, e.what());
    } catch (const Interrupted& e) {
      return stop(AnalysisStatus::interrupted,
                  fmt::format("{} (SIGINT or SIGTERM); the last converged time is t = {:g}",
                              e.what(), committed_.time));
    }
    result_.iterations += out.iterations;
    if (!ok) {
      const double mid = 0.5 * (committed_.time + t1);
      if (depth < model_.spec().solver.cutback && mid > committed_.time && mid < t1) {
        log_.info("step to t = {:g} failed ({}); cutting back to t = {:g}", t1, why, mid);
        targets.cut_back(mid);
        return std::nullopt;
      }
      return stop(
          AnalysisStatus::not_converged,
          fmt::format("step to t = {:g} did not converge after {} cut-backs: {}", t1, depth, why));
    }
    targets.reached();
    std::swap(committed_, trial_);
    if (heat_) heat_->committed(t1);
    const StepReport report = count_step(out, t1, targets.empty());
    log_step(model_, eq_, report, committed_, log_);
    return write_outputs(report, targets);
  }

  /// The report of the step just committed, counted in the result.
  StepReport count_step(const StepOutcome& out, double t1, bool last) {
    ++result_.steps;
    StepReport report;
    report.step = result_.steps;
    report.time = t1;
    report.iterations = out.iterations;
    report.residual = out.residual;
    report.delta_sigma = out.delta_sigma;
    report.delta_eps = out.delta_eps;
    report.factorizations = eq_.factorizations() - factorizations_before_;
    report.plastic_points = out.plastic_points;
    report.yield_excess = out.yield_excess;
    report.point_von_mises = out.point_von_mises;
    report.last = last;
    report.write_fields = report.last || report.step % model_.spec().output.every == 0;
    factorizations_before_ = eq_.factorizations();
    result_.factorizations = factorizations();
    return report;
  }

  /// The observer's outputs of a converged step and its checkpoint (when due), timed into
  /// Timings::output. An output that cannot be written (a full disk) stops the run as a step
  /// that fails does: what was written before stays (status 2). Root writes: every rank
  /// learns it.
  std::optional<AnalysisResult> write_outputs(const StepReport& report,
                                              const StepTargets& targets) {
    std::string output_failure;
    {
      ScopedTimer timer(timings_.output);
      try {
        observer_.step_done(report, committed_,
                            recover_fields(model_, committed_, report.write_fields));
      } catch (const OutputError& e) {
        output_failure = e.what();
      }
      if (sink_) {
        unwritten_ = !report.last && !sink_->due(report);
        if (unwritten_) {
          unwritten_eq_ = eq_.memory();
          unwritten_pending_ = targets.pending();
        } else {
          try {
            write_checkpoint(eq_.memory(), targets.pending());  // collective
          } catch (const OutputError& e) {
            if (output_failure.empty()) output_failure = e.what();
          }
        }
      }
    }
    if (par::any(!output_failure.empty())) {
      unwritten_ = false;  // it would fail the same way
      return stop(AnalysisStatus::not_converged,
                  fmt::format("the outputs of step {} (t = {:g}) cannot be written: {}; what "
                              "was written before is kept",
                              report.step, report.time,
                              output_failure.empty() ? "see rank 0" : output_failure));
    }
    return std::nullopt;
  }

  int factorizations() const { return earlier_factorizations_ + eq_.factorizations(); }

  void write_checkpoint(EquilibriumMemory mem, std::vector<StepTarget> pending) {
    RunMemory run;
    run.equilibrium = std::move(mem);
    if (heat_) run.heat = heat_->memory();
    run.pending = std::move(pending);
    run.steps = result_.steps;
    run.iterations = result_.iterations;
    run.factorizations = factorizations();
    sink_->write(committed_, run);
  }

  /// The result of a run that stops for `why`, after the checkpoint of its last converged step
  /// if that is not written yet.
  AnalysisResult stop(AnalysisStatus status, std::string why) {
    result_.status = status;
    result_.factorizations = factorizations();
    result_.failure = std::move(why);
    log_.info("{}", result_.failure);
    if (sink_ && unwritten_) {
      try {
        write_checkpoint(std::move(unwritten_eq_), std::move(unwritten_pending_));
      } catch (const OutputError& e) {  // what was written before stays
        log_.warn(std::string("the checkpoint of the last converged step was not written: ") +
                  e.what());
      }
    }
    return result_;
  }

  const Model& model_;
  Equilibrium& eq_;
  HeatSolver* heat_;
  Log& log_;
  Timings& timings_;
  StepObserver& observer_;
  /// Checkpoints: at the steps the sink asks for, and at the last converged step of the run
  /// whatever ends it.
  CheckpointSink* sink_;
  const RunMemory* resume_;
  AnalysisResult result_;
  int factorizations_before_ = 0;   ///< the factorizations of this process before the step
  int earlier_factorizations_ = 0;  ///< of the run a restart continues
  State committed_;
  State trial_;
  /// The memory of a converged step whose checkpoint is not written yet (a failed attempt
  /// after it changes the iteration's memory).
  bool unwritten_ = false;
  EquilibriumMemory unwritten_eq_;
  std::vector<StepTarget> unwritten_pending_;
};

}  // namespace

AnalysisResult run_analysis(const Model& model, LinearSystem& system, Log& log, Timings& timings,
                            StepObserver& observer, HeatSolver* heat, const RunOptions& options) {
  std::unique_ptr<HeatSolver> own_heat;  // a caller that made none: on the case's own options
  if (!heat && model.has_heat()) {
    own_heat = make_heat_solver(model, log);
    heat = own_heat.get();
  }
  Equilibrium eq(model, system, log, timings, heat);
  if (observer.wants_iterates()) eq.observe_iterates(&observer);
  return StepLoop(model, eq, heat, log, timings, observer, options).run();
}

}  // namespace hencky
