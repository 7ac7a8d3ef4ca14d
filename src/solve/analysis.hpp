#pragma once
// The incremental step loop (report section 2). Each step solves for the displacement
// increment with the error correction (2.29)-(2.30); the iteration inside a step is written
// once, in residual form, and the schemes of solve/schemes.hpp plug into it as point laws.
#include <optional>
#include <vector>

#include "core/log.hpp"
#include "linalg/linear_system.hpp"
#include "solve/heat.hpp"
#include "solve/model.hpp"
#include "solve/state.hpp"

namespace hencky {

/// interrupted: SIGINT or SIGTERM (core/interrupt.hpp) stopped the run between iterations.
enum class AnalysisStatus { converged, not_converged, interrupted };

struct AnalysisResult {
  AnalysisStatus status = AnalysisStatus::converged;
  int steps = 0;
  int iterations = 0;
  int factorizations = 0;
  std::string failure;  ///< why the analysis stopped, when it did
};

/// What a run continues from besides its committed state (a checkpoint, output/checkpoint.hpp):
/// the memories of the equilibrium iteration and of the heat analysis, the step targets still
/// pending (cut-backs included), and the counts so far.
struct RunMemory {
  EquilibriumMemory equilibrium;
  std::optional<HeatMemory> heat;
  /// The targets queued after the last converged step, in order: cut-back targets and the case
  /// time they lead to (empty when the next target is simply the case's next time).
  std::vector<StepTarget> pending;
  int steps = 0, iterations = 0, factorizations = 0;
};

/// A checkpoint read back (restore_run): the committed state and the run's memory.
struct Restart {
  State committed;
  RunMemory run;
};

/// Where run_analysis writes checkpoints (output/checkpoint.hpp implements it).
class CheckpointSink {
 public:
  virtual ~CheckpointSink() = default;
  /// A checkpoint is due after this converged step (the last one's is written anyway).
  virtual bool due(const StepReport& report) const = 0;
  /// Writes one. Collective (point data is gathered); root writes.
  virtual void write(const State& committed, const RunMemory& run) = 0;
};

struct RunOptions {
  const Restart* resume = nullptr;  ///< continue from it (a restart), else start at t = 0
  CheckpointSink* checkpoints = nullptr;
};

/// `heat`: the heat analysis of a case with temperature: {from: heat} (make_heat_solver,
/// solve/driver.hpp; made here on the case's options when not given); its divergence stops
/// the run as a step's does.
AnalysisResult run_analysis(const Model& model, LinearSystem& system, Log& log, Timings& timings,
                            StepObserver& observer, HeatSolver* heat = nullptr,
                            const RunOptions& options = {});

}  // namespace hencky
