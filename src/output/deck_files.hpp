#pragma once
// The files a CalculiX deck run as the case asks for (docs/ccx-decks.md): MODEL.dat, the
// values of its *NODE PRINT and *EL PRINT requests in ccx 2.20's layout (printoutnode.f,
// printoutelem.f: the blocks' titles, one line per node or integration point, Fortran's
// i10 and 1p e13.6 fields), and MODEL.frd, its *NODE FILE and *EL FILE requests as nodal fields
// (output/frd_writer.hpp). Written beside the run's other outputs, at the increments the
// requests ask for.
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "solve/state.hpp"

namespace hencky {

class FrdWriter;
struct RecoveredFields;

class DeckFiles {
 public:
  /// Opens the files the model's requests need (OutputSpec::deck_dat, deck_frd) in `dir`.
  DeckFiles(const Model& model, const std::filesystem::path& dir);
  ~DeckFiles();
  /// The blocks of the requests that ask for this converged step.
  void step_done(const StepReport& report, const State& state, const RecoveredFields& fields);
  /// A restart at time `t` of a run whose outputs are in `old` and whose converged steps ended
  /// at `earlier` (up to t): its MODEL.dat blocks and MODEL.frd sets up to t are copied, and the
  /// increments of the deck step counted on from them (what the print frequencies need).
  void continue_from(const std::filesystem::path& old, double t,
                     const std::vector<double>& earlier);

 private:
  /// Counts the increment ending at t in its deck step (step_start_, increment_).
  void count_increment(double t);
  /// Whether request q asks for the step ending at t (the increment's count in its deck step).
  bool due(const DeckRequest& q, double t, int increment) const;
  /// The blocks of variable `variable` of request `index` (of OutputSpec::deck_requests).
  void node_block(std::size_t index, const std::string& variable, const State& state, double t);
  void element_block(std::size_t index, const std::string& variable, const State& state, double t);
  std::vector<int> nodes_of(const DeckRequest& q) const;
  std::vector<int> cells_of(const DeckRequest& q) const;

  const Model& model_;
  std::ofstream dat_;
  std::unique_ptr<FrdWriter> frd_;
  int frd_steps_ = 0;
  std::vector<std::vector<int>> members_;      ///< per request: its nodes or cells, by label
  std::vector<std::vector<int>> point_order_;  ///< per CellType: ccx_point_order
  double step_start_ = -1;  ///< the deck step the last increment was in (its start time)
  int increment_ = 0;       ///< increments counted in that deck step
};

/// The order of a cell type's integration points as ccx numbers them in the same rule (its
/// gauss.f for C3D4, C3D10, C3D8, C3D20, C3D6): ccx's point j is hencky's point order[j].
/// Empty when hencky's rule for the type is not ccx's (its points are then hencky's order).
std::vector<int> ccx_point_order(CellType type);

}  // namespace hencky
