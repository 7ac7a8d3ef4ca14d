#pragma once
// The model of a run on its ranks (app/): read and bound whole on each, or distributed, or each
// rank its file of a split mesh (docs/parallel.md).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "input/load_case.hpp"
#include "output/checkpoint.hpp"

namespace hencky::cli {

/// Whether the run distributes its mesh over the ranks: on several ranks, unless
/// HENCKY_REPLICATED=1 asks every rank to hold the whole mesh (for comparisons: the memory and
/// time of the two ways, bench/).
bool distributes_mesh();

/// A rank's model as run() loaded it, and what the log says of the whole.
struct Loaded {
  LoadedCase l;
  std::string mesh_line, parts_line;         // the whole mesh and its parts
  std::string split_line;                    // how a split mesh was read, where not each rank
                                             // its own file
  std::vector<std::string> contact_lines;    // the whole model's contact
  std::optional<CheckpointMesh> whole_mesh;  // root's record of it on a distributed mesh
};

/// The model of case `spec` on this rank: on a distributed mesh (`distribute`) each rank's part,
/// from root's whole mesh or, a split mesh on as many ranks as files, from each rank's own
/// file; else the whole model. Root checks that the output directory `dir` has room
/// (check_output_space). Returns 0, or the exit status when a rank failed (reported).
/// Collective.
int load_model(std::unique_ptr<Case> spec, bool distribute, const std::filesystem::path& dir,
               const SourceLocation& dir_where, Log& log, Loaded& out);

}  // namespace hencky::cli
