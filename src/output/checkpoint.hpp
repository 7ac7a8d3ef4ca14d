#pragma once
// Checkpoints and restart (docs/outputs.md, "Checkpoints"; docs/cli.md, `--restart`).
//
// A checkpoint holds everything a run continues from (Restart, solve/analysis.hpp): the
// displacements, every integration point's state, the contact states, the equilibrium
// iteration's and the heat analysis's memory, the pending step targets and the counts, in the
// container of checkpoint_file.hpp. Integration-point data is stored in the order of the whole
// mesh's cells, whatever the number of ranks that wrote it, so a run may restart on another
// number of ranks. Fingerprints of the mesh, of each region and of each material let a restart
// refuse a case that changed what the state was computed on, naming what changed.
//
// Why not HDF5: the state is a few dozen flat arrays that one process writes (the points are
// gathered to root, as the results are); a format of our own needs no library whose parser is
// not hardened against damaged files (ours is fuzzed: fuzz/), is read back with the same
// checks as every other input, and its layout is written down in checkpoint_file.hpp.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/log.hpp"
#include "output/checkpoint_file.hpp"
#include "solve/analysis.hpp"

namespace hencky {

/// What a checkpoint records of the whole mesh (its fingerprint, its regions', its counts): on a
/// distributed mesh, taken by the rank that read the mesh before it sent the parts out.
struct CheckpointMesh {
  std::int64_t fingerprint = 0;
  std::vector<std::string> region_names;
  std::vector<std::int64_t> region_prints;
  long long nodes = 0, cells = 0;
};
CheckpointMesh checkpoint_mesh(const Mesh& mesh);
/// The same record where no rank holds the whole mesh (each read its file of a split mesh):
/// root gathers the parts' nodes, cells and regions in the whole order and records that mesh
/// (transient, about 40 bytes per node on root). The record on root, nullopt elsewhere.
/// Collective.
std::optional<CheckpointMesh> checkpoint_mesh_of_parts(const Model& model);

/// The file's record of `run`; point data gathered from every rank (collective; the result is
/// complete on root only). On a distributed mesh (Model::part) the nodal data is gathered too,
/// in the whole mesh's order, and `whole` (root's) describes the mesh.
CheckpointFile checkpoint_of(const Model& model, const State& committed, const RunMemory& run,
                             const CheckpointMesh* whole = nullptr);

/// The run a checkpoint continues: InputError naming what differs when the model's mesh,
/// regions, materials, contacts or heat section are not those the checkpoint was written
/// with. `f` must be read whole on every rank; each takes its own points.
/// On a distributed mesh `whole` is the whole mesh's record (every rank's).
Restart restore_run(const Model& model, const CheckpointFile& f,
                    const CheckpointMesh* whole = nullptr);

/// One checkpoint of an output directory (its checkpoints/index.csv).
struct CheckpointEntry {
  int step = 0;
  double time = 0;
  std::filesystem::path file;  ///< absolute
};
/// The checkpoints of output directory `dir`, by step; an InputError at `where` when it has
/// none or its index cannot be read.
std::vector<CheckpointEntry> list_checkpoints(const std::filesystem::path& dir,
                                              const SourceLocation& where);
/// The file's bytes, checked (CheckpointFile::parse).
CheckpointFile read_checkpoint(const std::filesystem::path& file);

/// Writes the checkpoints of a run into `<dir>/checkpoints` (the ResultWriter's work
/// directory): every output.checkpoint converged steps and at the run's last, each file
/// written to a temporary name, flushed to disk and renamed, and the index after it, so a crash
/// while writing never loses the checkpoint before. Keeps the newest output.checkpoint_keep.
class CheckpointWriter final : public CheckpointSink {
 public:
  /// `earlier`: checkpoints carried over from the run a restart continues (already in `dir`).
  /// `whole`: the whole mesh's record, on root, when the model is a rank's part.
  CheckpointWriter(const Model& model, const std::filesystem::path& dir, Log& log,
                   std::vector<CheckpointEntry> earlier = {},
                   std::optional<CheckpointMesh> whole = std::nullopt);
  bool due(const StepReport& report) const override;
  void write(const State& committed, const RunMemory& run) override;
  int written() const { return written_; }

 private:
  void write_index() const;
  const Model& model_;
  std::filesystem::path dir_;
  Log& log_;
  std::optional<CheckpointMesh> whole_;
  std::vector<CheckpointEntry> entries_;
  int written_ = 0;
};

}  // namespace hencky
