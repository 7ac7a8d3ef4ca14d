#pragma once
// What `hencky run` and `hencky check` share once a model is loaded (input/load_case.hpp):
// its description for the log, and the linear solver of a run.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "solve/analysis.hpp"
#include "solve/model.hpp"

namespace hencky {

/// "1865 nodes, 320 elements (320 20-node hexahedron)"
std::string describe_mesh(const Mesh& mesh);
/// The same from counts: nodes, cells, and cells by type name.
std::string describe_counts(long long nodes, long long cells,
                            const std::map<std::string, long long>& by_type);
/// "2349 unknowns": the free displacements; for a heat analysis alone (HeatSpec::only) "261
/// temperatures", the nodes'.
std::string describe_unknowns(const Model& model, long long free, long long nodes);
/// One line per contact: its surface, nodes, those touching at t = 0 and the range of κ.
std::vector<std::string> describe_contact(const Model& model);

/// The linear solver of a run: the case's back end (solver.linear), or on more than one MPI
/// rank the PETSc one (MUMPS for `direct`, CG + GAMG for `iterative`), with a log line saying
/// so. `petsc_options` (the command line's) are added after the case's and win. On several
/// ranks the model then holds the integration points of this rank's cells only
/// (Model::set_partition). Collective.
std::unique_ptr<LinearSystem> make_run_solver(Model& model, Log& log,
                                              const std::string& petsc_options = "");

/// The heat analysis of a case with a heat section (none without one), on the same back end
/// as make_run_solver's. Collective.
std::unique_ptr<HeatSolver> make_heat_solver(const Model& model, Log& log,
                                             const std::string& petsc_options = "");

}  // namespace hencky
