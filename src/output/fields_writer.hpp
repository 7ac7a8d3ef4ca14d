#pragma once
// The fields files of the written steps (.vtu, or a .pvtu and one piece per rank), and the
// observer of the ranks that write only their pieces.
#include <filesystem>
#include <string>
#include <vector>

#include "output/step_values.hpp"
#include "output/vtu_writer.hpp"
#include "solve/analysis.hpp"

namespace hencky {

/// The fields files of the written steps. On one rank, step_NNNN.vtu: the whole mesh. On
/// several, one piece per rank, step_NNNN/rank_R.vtu: the cells whose integration points the
/// rank holds and the nodes they touch, with their Gmsh numbers (node_tag, element_tag: VTK's
/// GlobalIds), and root's step_NNNN.pvtu that lists the pieces. Collective on several ranks.
class FieldsWriter {
 public:
  FieldsWriter(const Model& model, std::filesystem::path dir);
  /// Writes the step's fields into the directory; returns the file results.pvd lists (on
  /// root). A rank that cannot write its piece is an OutputError on every rank, naming it.
  std::string write(const StepReport& report, const State& state, const RecoveredFields& fields);

 private:
  /// The names and widths of a fields file's arrays (their data left empty), for the .pvtu.
  struct Layout {
    std::vector<VtuField> point, cell;
    std::vector<VtuIntField> ints;
  };
  /// Writes this rank's fields file to `path` (nothing when empty) and returns its layout.
  Layout write_file(const std::filesystem::path& path, const State& state,
                    const RecoveredFields& fields);
  const Model& model_;
  std::filesystem::path dir_;
  bool pieces_ = false;
  // This rank's piece (several ranks): global numbers of its cells and nodes, its cells with
  // local node numbers, the nodes' coordinates and the Gmsh tags of both.
  std::vector<int> cells_, nodes_;
  CellSet cell_set_;
  std::vector<Vec3> x_;
  std::vector<long> node_tag_, cell_tag_;
  std::vector<int> ranks_with_cells_;  ///< the ranks that write a piece (the partition's)
  std::vector<double> zeros_;
  /// The nodal heat flux of the step being written: found in write(), on every rank (it sums
  /// over the ranks), before the ranks with cells write their pieces.
  std::vector<double> heat_flux_;
};

/// The observer of every rank but root on several ranks: its piece of the fields files in
/// root's work directory (`dir`, broadcast by the caller).
class PieceWriter final : public StepObserver {
 public:
  PieceWriter(const Model& model, std::filesystem::path dir)
      : model_(model), fields_(model, std::move(dir)) {}
  void step_done(const StepReport& report, const State& state,
                 const RecoveredFields& fields) override {
    step_values(model_, state, fields);  // this rank's share, for root
    if (report.write_fields) fields_.write(report, state, fields);
  }
  bool wants_iterates() const override { return model_.spec().output.iterations; }
  void iterate_done(const IterateReport&, const State& trial) override {
    step_values(model_, trial, recover_fields(model_, trial, false));  // for root's row
  }

 private:
  const Model& model_;
  FieldsWriter fields_;
};

}  // namespace hencky
