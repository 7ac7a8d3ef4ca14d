#pragma once
// The incremental step loop (report section 2). Each step solves for the displacement
// increment with the error correction (2.29)-(2.30); the iteration inside a step is written
// once, in residual form, and the schemes of solve/schemes.hpp plug into it as point laws.
#include <vector>

#include "core/log.hpp"
#include "linalg/linear_system.hpp"
#include "solve/heat.hpp"
#include "solve/model.hpp"
#include "solve/state.hpp"

namespace hencky {

enum class AnalysisStatus { converged, not_converged };

struct AnalysisResult {
  AnalysisStatus status = AnalysisStatus::converged;
  int steps = 0;
  int iterations = 0;
  int factorizations = 0;
  std::string failure;  ///< why the analysis stopped, when it did
};

/// `heat`: the heat analysis of a case with temperature: {from: heat} (make_heat_solver,
/// solve/driver.hpp; made here on the case's options when not given); its divergence stops
/// the run as a step's does.
AnalysisResult run_analysis(const Model& model, LinearSystem& system, Log& log, Timings& timings,
                            StepObserver& observer, HeatSolver* heat = nullptr);

}  // namespace hencky
