#pragma once
// The matrix of the equilibrium iteration and its solves: when the scheme's matrix is
// assembled again, the assembly of the points' matrices and the contact's G, the
// factorization (with the message that names a negative secant), and the solve of an iterate's
// correction with the inexact-Newton tolerance.
#include <vector>

#include "core/log.hpp"
#include "linalg/linear_system.hpp"
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
  void assemble_and_factorize(const State& c, const State& trial, bool new_elements);
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

  const Model& m_;
  LinearSystem& system_;
  IterateEvaluator& iterate_;
  Log& log_;
  Timings& timings_;
  bool updated_;                           ///< solver.geometry: updated
  bool changes_with_temperature_ = false;  ///< E or ν depend on a temperature that changes
  bool factorized_ = false;
  std::vector<Tangent> assembled_tangents_;
  bool options_checked_ = false;  ///< unused options of the back end were reported
  int factorizations_ = 0;
  std::vector<double> delta_;
};

}  // namespace hencky
