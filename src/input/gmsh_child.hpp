#pragma once
// Gmsh's work (meshing a .geo, converting an element order) in a child process. Gmsh 4.8 can
// crash inside its own code on a degenerate geometry (issue 47: a SIGSEGV meshing an extrusion
// of length 1e-30, in Gmsh's threads), where no check of ours comes first; in a child, such a
// crash is an input error naming the file instead of the end of hencky. The child is the
// program itself, started again (posix_spawn of /proc/self/exe, a fresh process: no fork of a
// process that holds OpenMP or MPI threads) with a first argument that its main() passes to
// child_main(); it writes the model it got to a temporary file that the parent reads back.
// Programs that do not enable it (the unit tests, the fuzz targets but msh_order) run Gmsh in
// their own process, as before.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "input/msh_data.hpp"

namespace hencky::gmsh_child {

/// The first argument that makes a start of the program the child.
inline constexpr const char* marker = "--gmsh-child";

/// What the child runs: Gmsh's part of reading `file` (through_gmsh in gmsh_reader.cpp).
using Work = std::function<MshData(const std::filesystem::path& file, bool geometry, int order,
                                   std::vector<std::string>* gmsh_log)>;

/// Called by a program whose main() hands `marker` starts to child_main: from then on
/// run() starts a child. `work` is what the child runs.
void enable(Work work);
bool enabled();

/// In the parent: runs `work` for `file` in a child and returns its model; the child's Gmsh
/// messages are appended to `gmsh_log` when given. A crash of the child (a signal) or an error
/// in it is an InputError naming `file`.
MshData run(const std::filesystem::path& file, bool geometry, int order,
            std::vector<std::string>* gmsh_log);

/// The child's main: argv = {program, marker, file, result file, geometry 0|1, order}. Returns
/// the process's exit status (0: a result was written, errors included).
int child_main(int argc, char** argv);

}  // namespace hencky::gmsh_child
