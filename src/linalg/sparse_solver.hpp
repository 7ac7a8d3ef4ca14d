#pragma once
// The serial back ends' factorization, on the upper triangle of the free dofs' matrix in
// compressed columns (CHOLMOD, and CG with incomplete Cholesky). The step loop does not see
// it: it works through LinearSystem (linear_system.hpp), whose serial implementation
// (serial_system.hpp) assembles the values and calls analyze() once per pattern, factorize()
// only when the values changed, and solve() per right-hand side.
#include <algorithm>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "linalg/sparse.hpp"

namespace hencky {

struct LinearSolverStats {
  int n_analyses = 0;
  int n_factorizations = 0;
  int n_solves = 0;
  double factor_flops = 0;     ///< floating-point operations of one numeric factorization
  double factor_nnz = 0;       ///< entries of the factor (direct) or of the preconditioner
  double matrix_nnz = 0;       ///< entries of the matrix stored (CHOLMOD: its upper triangle)
  long iterations = 0;         ///< total iterations (iterative back ends)
  std::string description;     ///< e.g. "CHOLMOD supernodal, METIS ordering"
};

class SparseSolver {
 public:
  virtual ~SparseSolver() = default;
  /// Symbolic work on the pattern (ordering, elimination tree). Once per pattern. `ordering`:
  /// the dofs' fill-reducing order to use (perm[k] is eliminated k-th); empty: the solver's own.
  virtual void analyze(const SymmetricPattern& pattern,
                       std::span<const std::int64_t> ordering = {}) = 0;
  /// Numeric factorization (or preconditioner set-up) of the upper-triangle values.
  /// Throws LinearSystemError when the matrix is singular or not positive definite.
  virtual void factorize(std::span<const double> values) = 0;
  virtual void solve(std::span<const double> rhs, std::span<double> x) = 0;
  virtual const LinearSolverStats& stats() const = 0;
  /// The relative residual the next solves of an iterative back end must reach: `rtol`, but
  /// never below the back end's own tolerance nor above 0.1. The step loop loosens it while the
  /// nonlinear residual is far from its tolerance (inexact Newton). Direct back ends ignore it.
  virtual void set_relative_tolerance(double /*rtol*/) {}
};

/// set_relative_tolerance's rule for a back end whose own tolerance is `floor`.
inline double forcing_tolerance(double rtol, double floor) {
  return std::clamp(rtol, floor, std::max(floor, 0.1));
}

enum class LinearSolverKind { direct, iterative };

/// The factor of a mesh's node graph (one unknown a node) under the nested-dissection ordering
/// the direct back end uses, by CHOLMOD's symbolic analysis: it predicts the factor of a system
/// with per_node dofs at every node (none prescribed) within a few % (entries_for, flops_for),
/// on a ninth of the dof graph's edges for per_node = 3. One analysis serves the displacement
/// and the temperature of the same mesh.
struct FactorEstimate {
  double entries = 0;  ///< of the node graph's factor
  double flops = 0;
  int n_nodes = 0;
  std::vector<std::int64_t> node_order;  ///< the nodes' ordering analysed (every node)
  /// × per_node² less the upper halves of the diagonal blocks; flops × per_node³.
  double entries_for(int per_node) const {
    const double k = per_node;
    return entries * k * k - n_nodes * k * (k - 1) / 2;
  }
  double flops_for(int per_node) const { return flops * per_node * per_node * per_node; }
};
FactorEstimate estimate_factor(const CellSet& cells, int n_nodes);

/// `tolerance` is the relative residual of the iterative back end.
std::unique_ptr<SparseSolver> make_sparse_solver(LinearSolverKind kind, double tolerance = 1e-10);

}  // namespace hencky
