#pragma once
// Loading a case and its mesh into a Model: what `hencky run` and `hencky check` share, and
// what tests use to run a case in-process and look at the final state.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "solve/analysis.hpp"
#include "solve/driver.hpp"
#include "solve/model.hpp"
#include "spec/case.hpp"

namespace hencky {

struct LoadedCase {
  std::unique_ptr<Case> spec;  ///< heap-held: the model keeps pointers into it
  std::unique_ptr<Model> model;
  double mesh_seconds = 0, setup_seconds = 0;
};

/// The files of a split mesh (mesh.split), in order.
std::vector<std::filesystem::path> piece_files(const MeshSpec& mesh);

/// Reads the case, reads (or meshes) its mesh and binds them. Throws InputError.
LoadedCase load_case(const std::filesystem::path& case_file, Log& log);
/// The same for a case already read: reads (or meshes) its mesh and binds them.
LoadedCase load_case(std::unique_ptr<Case> spec, Log& log);

/// Keeps the reports and the last committed state (for tests and tools).
class KeepLastState final : public StepObserver {
 public:
  void step_done(const StepReport& report, const State& state, const RecoveredFields&) override {
    reports.push_back(report);
    last = state;
  }
  std::vector<StepReport> reports;
  State last;
};

/// Runs a case in-process with the direct solver (or the case's choice), no files written.
struct InProcessRun {
  LoadedCase loaded;
  AnalysisResult result;
  KeepLastState states;
  LinearSolverStats solver_stats;  ///< analyses, factorizations, solves of the run
  /// The heat analysis's steps, Newton iterations and GMRES iterations (heat section only).
  int heat_steps = 0, heat_iterations = 0, heat_gmres_iterations = 0;
};
std::unique_ptr<InProcessRun> run_in_process(const std::filesystem::path& case_file, Log& log,
                                             const std::string& petsc_options = "");

}  // namespace hencky
