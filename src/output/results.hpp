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
#include "output/deck_files.hpp"
#include "output/fields_writer.hpp"
#include "output/step_values.hpp"
#include "output/vtu_writer.hpp"
#include "solve/analysis.hpp"

namespace hencky {

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
  /// output.iterations: a row of iterations.csv per iterate (its measures, and the probes'
  /// stress and ε̃^{e+p} at the iterate, recovered as for a step).
  bool wants_iterates() const override { return model_.spec().output.iterations; }
  void iterate_done(const IterateReport& report, const State& trial) override;

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
  void write_law_values(const std::vector<ProbeValues>& probe_row, nlohmann::json& probes);
  void write_history(const StepReport& report, const State& state, const StepValues& values);
  /// Keeps the run's largest values and the last balance (report()).
  void remember(const StepValues& values, const StepReport& report);
  const Model& model_;
  std::filesystem::path final_dir_, work_dir_;
  Log& log_;
  struct Peak {
    StepValues::Largest at;
    double time = 0;
  };
  /// peak_point_von_mises_: of the integration points' stresses (the nodal field's is recovered:
  /// extrapolated from them and averaged, and can stand far above them).
  Peak peak_von_mises_, peak_displacement_, peak_eps_p_eq_, peak_point_von_mises_;
  /// The largest yield excess of the converged steps (value < 0 while none exceeds), and
  /// whether the model has plasticity (-inf: none).
  Peak peak_yield_excess_;
  std::vector<std::pair<double, double>> peak_contact_;  ///< each contact's largest force, when
  double balance_time_ = -1;  ///< of the last converged step (-1: none yet)
  StepValues::Balance balance_;
  std::ofstream history_;
  std::ofstream iterations_;  ///< iterations.csv (output.iterations)
  std::unique_ptr<PvdWriter> pvd_;
  std::unique_ptr<FieldsWriter> fields_;
  std::unique_ptr<DeckFiles> deck_files_;  ///< a deck's MODEL.dat and MODEL.frd
  nlohmann::json final_values_;
  std::string header_;  ///< history.csv's first line
  bool finished_ = false;
};

}  // namespace hencky
