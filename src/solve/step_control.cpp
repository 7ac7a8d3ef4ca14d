// Step control: which steps to take (the case's times, one at a time), cut-back of a step that
// fails, the log line and the observer of every converged step. Whether a step converges is
// the equilibrium iteration's business (equilibrium.hpp).
#include <fmt/format.h>

#include <chrono>
#include <deque>

#include "core/interrupt.hpp"
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
    why = fmt::format("no convergence in {} iterations (relative residual {:.3e})", out.iterations,
                      out.residual);
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
  if (model.has_plasticity()) {
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

}  // namespace

AnalysisResult run_analysis(const Model& model, LinearSystem& system, Log& log, Timings& timings,
                            StepObserver& observer, HeatSolver* heat, const RunOptions& options) {
  const auto& spec = model.spec().solver;
  std::unique_ptr<HeatSolver> own_heat;  // a caller that made none: on the case's own options
  if (!heat && model.has_heat()) {
    own_heat = make_heat_solver(model, log);
    heat = own_heat.get();
  }
  Equilibrium eq(model, system, log, timings, heat);
  AnalysisResult result;
  int factorizations_before = 0;   // the factorizations of this process before the step
  int earlier_factorizations = 0;  // of the run a restart continues
  State committed;
  const RunMemory* resume = options.resume ? &options.resume->run : nullptr;
  if (resume) {
    committed = options.resume->committed;
    if (heat && resume->heat) heat->resume(*resume->heat);
    eq.resume(committed, resume->equilibrium);
    // The restart's factorization of the matrix the run had: in the summary's count, not in
    // the next step's (whose history row is then the uninterrupted run's).
    factorizations_before = eq.factorizations();
    result.steps = resume->steps;
    result.iterations = resume->iterations;
    earlier_factorizations = resume->factorizations;
  } else {
    committed = eq.initial_state();
  }
  State trial = committed;
  StepTargets targets(spec.times, committed.time,
                      resume ? resume->pending : std::vector<StepTarget>());
  auto factorizations = [&] { return earlier_factorizations + eq.factorizations(); };
  // Checkpoints: at the steps the sink asks for, and at the last converged step of the run
  // whatever ends it. The memory of a converged step whose checkpoint is not written yet is
  // kept (a failed attempt after it changes the iteration's memory).
  CheckpointSink* sink = options.checkpoints;
  bool unwritten = false;
  EquilibriumMemory unwritten_eq;
  std::vector<StepTarget> unwritten_pending;
  auto write_checkpoint = [&](EquilibriumMemory mem, std::vector<StepTarget> pending) {
    RunMemory run;
    run.equilibrium = std::move(mem);
    if (heat) run.heat = heat->memory();
    run.pending = std::move(pending);
    run.steps = result.steps;
    run.iterations = result.iterations;
    run.factorizations = factorizations();
    sink->write(committed, run);
  };
  auto stop = [&](AnalysisStatus status, std::string why) {
    result.status = status;
    result.factorizations = factorizations();
    result.failure = std::move(why);
    log.info("{}", result.failure);
    if (sink && unwritten) {
      try {
        write_checkpoint(std::move(unwritten_eq), std::move(unwritten_pending));
      } catch (const OutputError& e) {  // what was written before stays
        log.warn(std::string("the checkpoint of the last converged step was not written: ") +
                 e.what());
      }
    }
    return result;
  };
  while (!targets.empty()) {
    const double t1 = targets.time();
    const int depth = targets.depth();
    StepOutcome out;
    std::string why;
    bool ok = false;
    try {
      if (par::any(interrupt_requested()))
        throw Interrupted(fmt::format("interrupted before the step to t = {:g}", t1));
      ok = attempt(model, eq, committed, t1, trial, result.steps == 0, out, why);
    } catch (const HeatDivergence& e) {  // the heat analysis cut its own steps back already
      return stop(AnalysisStatus::not_converged, e.what());
    } catch (const Interrupted& e) {
      return stop(AnalysisStatus::interrupted,
                  fmt::format("{} (SIGINT or SIGTERM); the last converged time is t = {:g}",
                              e.what(), committed.time));
    }
    result.iterations += out.iterations;
    if (!ok) {
      const double mid = 0.5 * (committed.time + t1);
      if (depth < spec.cutback && mid > committed.time && mid < t1) {
        log.info("step to t = {:g} failed ({}); cutting back to t = {:g}", t1, why, mid);
        targets.cut_back(mid);
        continue;
      }
      return stop(
          AnalysisStatus::not_converged,
          fmt::format("step to t = {:g} did not converge after {} cut-backs: {}", t1, depth, why));
    }
    targets.reached();
    std::swap(committed, trial);
    if (heat) heat->committed(t1);
    ++result.steps;
    StepReport report;
    report.step = result.steps;
    report.time = t1;
    report.iterations = out.iterations;
    report.residual = out.residual;
    report.delta_sigma = out.delta_sigma;
    report.delta_eps = out.delta_eps;
    report.factorizations = eq.factorizations() - factorizations_before;
    report.plastic_points = out.plastic_points;
    report.last = targets.empty();
    report.write_fields = report.last || report.step % model.spec().output.every == 0;
    factorizations_before = eq.factorizations();
    result.factorizations = factorizations();
    log_step(model, eq, report, committed, log);
    const auto t0 = std::chrono::steady_clock::now();
    // An output that cannot be written (a full disk) stops the run as a step that fails does:
    // what was written before stays (status 2). Root writes: every rank learns it.
    std::string output_failure;
    try {
      observer.step_done(report, committed, recover_fields(model, committed, report.write_fields));
    } catch (const OutputError& e) {
      output_failure = e.what();
    }
    if (sink) {
      unwritten = !report.last && !sink->due(report);
      if (unwritten) {
        unwritten_eq = eq.memory();
        unwritten_pending = targets.pending();
      } else {
        try {
          write_checkpoint(eq.memory(), targets.pending());  // collective
        } catch (const OutputError& e) {
          if (output_failure.empty()) output_failure = e.what();
        }
      }
    }
    timings.output += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (par::any(!output_failure.empty())) {
      unwritten = false;  // it would fail the same way
      return stop(
          AnalysisStatus::not_converged,
          fmt::format("the outputs of step {} (t = {:g}) cannot be written: {}; what "
                      "was written before is kept",
                      report.step, t1, output_failure.empty() ? "see rank 0" : output_failure));
    }
  }
  return result;
}

}  // namespace hencky
