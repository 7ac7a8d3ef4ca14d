#pragma once
// The matrix of the equilibrium iteration and its solves: when the scheme's matrix is
// assembled again, the assembly of the points' matrices and the contact's G, the
// factorization (with the message that names a negative secant), and the solve of an iterate's
// correction with the inexact-Newton tolerance.
#include <vector>

#include "core/log.hpp"
#include "linalg/linear_system.hpp"
#include "solve/element_matrix.hpp"
#include "solve/iterate.hpp"
#include "solve/schemes.hpp"

namespace hencky {

class StepMatrix {
 public:
  StepMatrix(const Model& m, LinearSystem& system, IterateEvaluator& iterate, Log& log,
             Timings& timings);

  /// Whether the elements' part of the matrix is assembled again before the solve of
  /// `iteration` under the scheme's `policy`: never assembled, a new step whose matrix
  /// depends on the temperature or the configuration, or a point's matrix that changed where
  /// the policy follows it. `first_iteration`: the iteration the step's points started from
  /// (1 when the step began again, Equilibrium::begin_again).
  bool needs_elements(int iteration, int first_iteration, bool tangent_changed,
                      MatrixPolicy policy) const;
  /// Assembles the matrix (the elements' part only when `new_elements` or when it was never
  /// kept: a change of the contact alone starts from the elements' part of the last assembly)
  /// and factorizes it.
  /// `iteration`: the iterate's (0 at the step's start; under `updated` a matrix that is not
  /// positive definite is then the structure's own, else the iterate's, StepStart::matrix).
  /// `at_start`: under `updated`, the matrix of the step's start whatever the iterate
  /// (StepStart::at_start), for the schemes whose matrix stays fixed through the step.
  void assemble_and_factorize(const State& c, const State& trial, bool new_elements,
                              int iteration, bool at_start);
  /// Under `updated`, the step's prescribed displacements (trial.u − c.u at the prescribed
  /// dofs) spread into the body before its first iterate is evaluated: the free dofs move by
  /// K_ff⁻¹(−K_fp Δu_p) with the matrix of the step's start, so that a boundary moved by more
  /// than its cells' size does not crush them (the iteration then corrects the rest). Returns
  /// ‖K Δu_p‖ over the whole model, the forces of the prescribed motion on the body held as it
  /// was (0 when nothing is prescribed to move): a force scale of the step. Collective.
  double spread_prescribed(const State& c, State& trial);
  /// Under `updated`, after the matrix of iterate `iteration` (> 0) failed to factorize or to
  /// solve (e): the matrix assembled again with the scheme's matrix on the step's Green strain
  /// and no initial-stress part, and factorized. Returns false (nothing done) where that does
  /// not apply: the caller rethrows.
  bool fall_back(const State& c, const State& trial, int iteration, const LinearSystemError& e);
  /// The correction of the iterate whose residual is iterate.rhs() (relative `residual`), into
  /// correction().
  void solve(double residual);
  std::vector<double>& correction() { return delta_; }
  const std::vector<double>& correction() const { return delta_; }

  int factorizations() const { return factorizations_; }
  bool factorized() const { return factorized_; }
  /// The points' matrices in the elements' part of the factorized matrix.
  const std::vector<Tangent>& assembled_tangents() const { return assembled_tangents_; }

 private:
  void factorize();
  /// The matrix of the iterate (`matrix`: under `updated`, StepStart::matrix).
  void assemble(const State& c, const State& trial, bool new_elements, UpdatedMatrix matrix);

  const Model& m_;
  LinearSystem& system_;
  IterateEvaluator& iterate_;
  Log& log_;
  Timings& timings_;
  bool updated_;                           ///< solver.geometry: updated
  bool changes_with_temperature_ = false;  ///< E or ν depend on a temperature that changes
  bool factorized_ = false;
  bool at_start_ = false;  ///< the last assembly's StepStart::at_start
  UpdatedMatrix last_matrix_ = UpdatedMatrix::exact;  ///< the last assembly's StepStart::matrix
  bool start_factorized_ = false;  ///< the factorized matrix is spread_prescribed's, unchanged
  std::vector<Tangent> assembled_tangents_;
  bool options_checked_ = false;  ///< unused options of the back end were reported
  int factorizations_ = 0;
  std::vector<double> delta_;
};

}  // namespace hencky
