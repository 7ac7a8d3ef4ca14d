#pragma once
// `hencky run` (docs/cli.md): the analysis of a case, its outputs and its checkpoints.
#include <optional>
#include <string>

namespace hencky::cli {

/// The command line's words for a run.
struct RunRequest {
  std::string case_path;
  std::string out_dir;  ///< -o (empty: the case's output.dir)
  bool quiet = false;
  std::string petsc_options;    ///< --petsc, joined
  std::string threads_warning;  ///< set_threads' (empty: none)
  std::string restart;          ///< --restart DIR (empty: none)
  std::optional<double> from;   ///< --from T
};

/// Runs the analysis and writes its outputs. Returns the exit status (docs/cli.md): 0
/// converged, 1 bad input, 2 a step did not converge, 4 interrupted. Collective.
int run(const RunRequest& request);

}  // namespace hencky::cli
