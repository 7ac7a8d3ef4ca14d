#pragma once
// The incremental step loop (report section 2) for the thermo-elastic model. Each step
// solves for the displacement increment with the error correction (2.29)-(2.30); the
// iteration inside a step is written once so that the nonlinear schemes plug into it.
#include <vector>

#include "io/log.hpp"
#include "linalg/linear_solver.hpp"
#include "solve/model.hpp"

namespace hencky {

/// Everything that describes the body at one converged time (committed) or at the current
/// iterate (trial). Integration-point data is indexed by Model::point_offset(cell) + q.
struct State {
  double time = 0;
  std::vector<double> u;                    ///< displacement, 3 per node
  std::vector<double> nodal_temperature;    ///< per node
  std::vector<Voigt> stress;                ///< per integration point
  std::vector<double> temperature;          ///< per integration point
  std::vector<ElasticConstants> constants;  ///< E, ν, α at the point's temperature
  std::vector<double> f_ext;                ///< external nodal forces, 3 per node
  std::vector<double> f_int;                ///< internal nodal forces ∫Bᵀσ, 3 per node
};

struct StepReport {
  int step = 0;            ///< 1-based count of converged steps
  double time = 0;
  int iterations = 0;
  double residual = 0;     ///< ‖F_ext − F_int‖ on the free dofs, relative
  bool last = false;       ///< the final step of the analysis
};

struct Timings {
  double assembly = 0, factorization = 0, solve = 0, material = 0, output = 0;
};

class StepObserver {
 public:
  virtual ~StepObserver() = default;
  /// Called after every converged step with the committed state.
  virtual void step_done(const StepReport& report, const State& state) = 0;
};

enum class AnalysisStatus { converged, not_converged };

struct AnalysisResult {
  AnalysisStatus status = AnalysisStatus::converged;
  int steps = 0;
  int iterations = 0;
  std::string failure;  ///< why the analysis stopped, when it did
};

AnalysisResult run_analysis(const Model& model, LinearSolver& solver, Log& log, Timings& timings,
                            StepObserver& observer);

}  // namespace hencky
