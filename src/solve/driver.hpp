#pragma once
// Loading a case and its mesh into a Model: what `hencky run` and `hencky check` share, and
// what tests use to run a case in-process and look at the final state.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "io/case.hpp"
#include "io/log.hpp"
#include "solve/analysis.hpp"
#include "solve/model.hpp"

namespace hencky {

struct LoadedCase {
  std::unique_ptr<Case> spec;    ///< heap-held: the model keeps pointers into it
  std::unique_ptr<Model> model;
  double mesh_seconds = 0, setup_seconds = 0;
};

/// Reads the case, reads (or meshes) its mesh and binds them. Throws InputError.
LoadedCase load_case(const std::filesystem::path& case_file, Log& log);
/// The same for a case already read: reads (or meshes) its mesh and binds them.
LoadedCase load_case(std::unique_ptr<Case> spec, Log& log);

/// "1865 nodes, 320 elements (320 20-node hexahedron)"
std::string describe_mesh(const Mesh& mesh);
/// One line per contact: its surface, nodes, those touching at t = 0 and the range of κ.
std::vector<std::string> describe_contact(const Model& model);

/// The linear solver of a run: the case's back end (solver.linear), or on more than one MPI
/// rank the PETSc one (MUMPS for `direct`, CG + GAMG for `iterative`), with a log line saying
/// so. `petsc_options` (the command line's) are added after the case's and win. On several
/// ranks the model then holds the integration points of this rank's cells only
/// (Model::hold_points). Collective.
std::unique_ptr<LinearSolver> make_run_solver(Model& model, Log& log,
                                              const std::string& petsc_options = "");

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
};
std::unique_ptr<InProcessRun> run_in_process(const std::filesystem::path& case_file, Log& log,
                                             const std::string& petsc_options = "");

}  // namespace hencky
