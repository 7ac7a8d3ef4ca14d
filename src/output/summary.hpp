#pragma once
// summary.json (docs/outputs.md): the run's figures (status, counts, the linear solvers', wall
// times, memory) beside the results' last values and the run's report, which the ResultWriter
// keeps. The command line gathers the figures; this writes them.
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "linalg/sparse_solver.hpp"
#include "output/results.hpp"
#include "solve/analysis.hpp"

namespace hencky {

/// What summary.json says of a run besides the ResultWriter's values, on root.
struct RunFigures {
  std::string title;
  int status = 0;  ///< the exit status: 0 converged, 2 not converged, 4 interrupted
  /// --restart: the output directory and the checkpoint's step and time the run continued from.
  struct From {
    std::string dir;
    int step = 0;
    double time = 0;
  };
  std::optional<From> restart;
  std::optional<int> checkpoints;  ///< checkpoints written, when the run writes any
  AnalysisResult result;           ///< steps, iterations, factorizations, failure
  std::string scheme;
  std::string formulation;  ///< solver.formulation: "hencky" or "report"
  long long dofs = 0, nodes = 0, elements = 0;  ///< of the whole model
  int integration_points = 0;
  int threads = 0, ranks = 0;
  LinearSolverStats linear_solver;
  std::string blas_kernels;  ///< OpenBLAS's kernels (empty: unknown)
  std::vector<std::string> warnings;
  /// Wall time (s) of reading the mesh, of the setup, of the analysis's phases and of all.
  double mesh_seconds = 0, setup_seconds = 0;
  Timings timings;
  double total_seconds = 0;
  /// The heat analysis, when the case has one.
  struct Heat {
    int steps = 0, iterations = 0;
    LinearSolverStats linear_solver;
  };
  std::optional<Heat> heat;
  /// The peak resident memory of the largest rank, and on several ranks their total (bytes).
  long long peak_memory_bytes = 0;
  std::optional<long long> peak_memory_bytes_all_ranks;
};

/// summary.json's object: `figures`, the last values `final_values` (ResultWriter::final_values)
/// and the run's `report` (ResultWriter::report).
nlohmann::json summary_json(const RunFigures& figures, const nlohmann::json& final_values,
                            const nlohmann::json& report);

/// The end of a run's outputs, on root: the report's lines and the time of each phase in the
/// log, summary.json written and the results moved into place (ResultWriter::finish).
void finish_results(ResultWriter& writer, const RunFigures& figures, Log& log);

}  // namespace hencky
