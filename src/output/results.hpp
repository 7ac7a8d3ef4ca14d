#pragma once
// The outputs of the contract: results.pvd + one .vtu per written step, history.csv,
// summary.json and hencky.log. Everything is written into a fresh directory next to the
// requested one and moved into place only when the run ends with converged steps to show
// (status 0 or 2): a run that fails on input or crashes never touches earlier results.
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "output/checkpoint.hpp"
#include "output/vtu_writer.hpp"
#include "solve/analysis.hpp"
#include "solve/recovery.hpp"

namespace hencky {

/// Nodal stress recovered from the integration points (recover_fields, solve/recovery.hpp):
/// each cell extrapolates its point values to its nodes, nodes average over their cells.
/// Collective on several ranks, like recover_fields.
std::vector<Voigt> recover_nodal_stress(const Model& model, const State& state);

struct ProbeValues {
  Vec3 displacement = Vec3::Zero();
  Voigt stress = Voigt::Zero();
  double von_mises = 0;
  double temperature = 0;
  double equivalent_plastic_strain = 0;
  /// Engineering shears; zero where the fields were not given (the overload without them).
  Voigt strain = Voigt::Zero(), elastic_strain = Voigt::Zero(), plastic_strain = Voigt::Zero(),
        thermal_strain = Voigt::Zero();
  double eps_ep = 0;  ///< ε̃^{e+p}
};
ProbeValues probe_values(const Model& model, const Probe& probe, const State& state,
                         const std::vector<Voigt>& nodal_stress,
                         std::span<const double> nodal_eps_p_eq = {});
/// Every value of a probe, the strains included, from the recovered fields.
ProbeValues probe_values(const Model& model, const Probe& probe, const State& state,
                         const RecoveredFields& fields);

/// Reaction of each region of output.reactions: Σ over its nodes of (F_int − F_ext −
/// F_contact); on several ranks this rank's share, over the nodes it owns (step_values sums).
std::vector<Vec3> region_reactions(const Model& model, const State& state);

/// Heat into the body (W) through each region of output.reactions with a temperature condition
/// (reaction.<region>.heat), then through each region of output.heat_flows
/// (heat_flow.<region>): the sums of the flows of the heat.boundary entries that name it.
struct HeatFlows {
  std::vector<double> reactions, flows;
};
HeatFlows heat_flows(const Model& model, const State& state);

/// contact_totals (contact/contact.hpp) of every contact of the model, in case order.
std::vector<ContactTotals> contact_totals(const Model& model, const State& state);

/// Nodal contact fields: pressure (normal force over the tributary area), state (0 free,
/// 1 contact, 2 separating) and gap (signed distance from the surface; 0 off the contact
/// regions). Empty vectors without contact.
struct NodalContact {
  std::vector<double> pressure, state, gap;
};
NodalContact nodal_contact(const Model& model, const State& state);

/// The values of a converged step that history.csv and summary.json report: each probe
/// evaluated by the rank that owns its cell, each reaction and contact total summed (largest
/// values: the largest) over the nodes each rank owns, and gathered on root. Collective; on the
/// other ranks the result is not complete.
struct StepValues {
  std::vector<ProbeValues> probes;
  std::vector<Vec3> reactions;
  std::vector<ContactTotals> contacts;
  /// The largest value of a nodal field and its node (file number and undeformed position).
  struct Largest {
    double value = -1;  ///< < 0: the field is not there (no plasticity)
    long node = 0;
    Vec3 x = Vec3::Zero();
  };
  /// Of the recovered nodal fields written to the VTU files: the von Mises stress, |u| and ε̃p.
  Largest von_mises, displacement, eps_p_eq;
  /// The equilibrium a user checks by hand, over the whole model: the supports' reactions (at
  /// every prescribed node), the applied loads and the rigid surfaces' forces; they sum to
  /// zero (to the residual).
  struct Balance {
    Vec3 supports = Vec3::Zero(), loads = Vec3::Zero(), contact = Vec3::Zero();
    double force_scale = 0;  ///< Σ over the nodes of |F_int|
    /// |supports + loads + contact| over the largest of them and force_scale.
    double imbalance() const;
  };
  Balance balance;
};
StepValues step_values(const Model& model, const State& state, const RecoveredFields& fields);

/// Checks that `dir` can be the output directory of a run, before the run starts: its folder
/// exists, `dir` is absent, empty or holds hencky results (so that a mistyped path never
/// replaces unrelated files), and the work directory `<dir>.partial-<pid>` next to it can be
/// created and written (it is created and removed again: nothing is left behind). Throws an
/// InputError at `where` (the case's output.dir, or the command line's -o).
void check_output_dir(const std::filesystem::path& dir, const SourceLocation& where);

/// Checks, before the analysis, that the file system of output directory `dir` has room for
/// the run's outputs, estimated from the model (a fields file per written step, a checkpoint
/// per checkpoint step, the newest output.checkpoint_keep of them): an InputError at `where`
/// when it cannot hold even the first step's, a warning when it cannot hold them all.
void check_output_space(const Model& model, const std::filesystem::path& dir,
                        const SourceLocation& where, Log& log);

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

 private:
  const Model& model_;
  FieldsWriter fields_;
};

class ResultWriter final : public StepObserver {
 public:
  /// Creates the work directory next to `final_dir` and starts history.csv, hencky.log and
  /// results.pvd in it; what check_output_dir checks is an InputError at `where` here too.
  ResultWriter(const Model& model, std::filesystem::path final_dir, Log& log,
               const SourceLocation& where);
  ~ResultWriter() override;
  const std::filesystem::path& work_dir() const { return work_dir_; }

  void step_done(const StepReport& report, const State& state,
                 const RecoveredFields& fields) override;

  /// A restart (`--restart`): takes over from the output directory `old` what its run wrote up
  /// to step `steps` (its history rows, its fields' files and their series entries, and its
  /// checkpoints, listed in `checkpoints`), so that this run's outputs continue them. Files are
  /// hard-linked where the file system allows it (copied otherwise). Returns the checkpoints
  /// now in the work directory. A history whose columns differ (the output section changed) is
  /// kept whole as history-before-restart.csv.
  std::vector<CheckpointEntry> continue_from(const std::filesystem::path& old, int steps,
                                             const std::vector<CheckpointEntry>& checkpoints);

  /// Writes summary.json and moves the directory into place (replacing the old one).
  void finish(nlohmann::json summary);
  /// Deletes the work directory (the run stopped on bad input: nothing is kept).
  void abandon();
  /// The last probe and reaction values, as the summary reports them.
  const nlohmann::json& final_values() const { return final_values_; }
  /// The run's report (summary.json's `report`): the largest von Mises stress, displacement
  /// and equivalent plastic strain of every converged step's nodal fields, where and when; the
  /// last step's balance of reactions, loads and contact forces; each contact's largest force.
  nlohmann::json report() const;
  /// The same as lines for hencky.log and the terminal.
  std::vector<std::string> report_lines() const;

 private:
  void write_history(const StepReport& report, const State& state, const StepValues& values);
  /// Keeps the run's largest values and the last balance (report()).
  void remember(double time, const StepValues& values);
  const Model& model_;
  std::filesystem::path final_dir_, work_dir_;
  Log& log_;
  struct Peak {
    StepValues::Largest at;
    double time = 0;
  };
  Peak peak_von_mises_, peak_displacement_, peak_eps_p_eq_;
  std::vector<std::pair<double, double>> peak_contact_;  ///< each contact's largest force, when
  double balance_time_ = -1;  ///< of the last converged step (-1: none yet)
  StepValues::Balance balance_;
  std::ofstream history_;
  std::unique_ptr<PvdWriter> pvd_;
  std::unique_ptr<FieldsWriter> fields_;
  nlohmann::json final_values_;
  std::string header_;  ///< history.csv's first line
  bool finished_ = false;
};

}  // namespace hencky
