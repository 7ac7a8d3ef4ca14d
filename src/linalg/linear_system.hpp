#pragma once
// The global linear system as the step loop sees it, one interface for every back end: the
// matrix assembled from the cells' matrices (and, with contact, 3x3 blocks coupling two nodes),
// factorized (or its preconditioner set up) when it changed, solved per right-hand side. The
// serial back ends (serial_system.hpp: CHOLMOD, CG) and the PETSc one (petsc_solver.hpp)
// implement all of it; failures are typed (LinearSystemError, SolverOptionsError in
// core/error.hpp).
//
// The order of a matrix's assembly is always: assemble_cells, then (with contact) keep_cells,
// the contact's add_block calls, factorize. A change of the contact alone starts from
// restore_cells instead of assembling the cells again.
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "linalg/assembler.hpp"
#include "linalg/sparse_solver.hpp"

namespace hencky {

class LinearSystem {
 public:
  /// Fills b.ke (zeroed before the call) with the matrix of a cell, 3 dofs per node in the
  /// order of the cell's nodes. Called in parallel for cells that share no node.
  using CellMatrix = std::function<void(int cell, CellBuffers& b)>;

  virtual ~LinearSystem() = default;

  /// A new matrix from the cells' matrices (this rank's cells). Collective.
  virtual void assemble_cells(const CellMatrix& cell_matrix) = 0;
  /// Keeps a copy of the matrix just assembled from the cells (before any block is added).
  virtual void keep_cells() = 0;
  /// Starts the matrix again from the kept copy; false when nothing was kept.
  virtual bool restore_cells() = 0;
  /// Adds a 3x3 block coupling the dofs of nodes a (rows) and b (columns); rows and columns of
  /// prescribed dofs are skipped. Not thread-safe.
  virtual void add_block(int a, int b, const Mat3& block) = 0;
  /// Factorizes the matrix as assembled (or sets the preconditioner up). Throws
  /// LinearSystemError when the matrix cannot be factorized, SolverOptionsError when the
  /// back end's options do not apply. Collective.
  virtual void factorize() = 0;
  /// x = K⁻¹ rhs on the free dofs (DofMap numbering, full length on every rank). Throws
  /// LinearSystemError. Collective.
  virtual void solve(std::span<const double> rhs, std::span<double> x) = 0;
  /// The relative residual the next solves of an iterative back end must reach: `rtol`, but
  /// never below the back end's own tolerance nor above 0.1 (LinearSolver's forcing rule);
  /// no effect on a direct solve.
  virtual void set_relative_tolerance(double rtol) = 0;
  /// Options given to the back end that it did not use (misspelt, or for a solver not in use):
  /// meaningful after the first solve.
  virtual std::vector<std::string> unused_options() const = 0;
  /// The cells this rank assembles and updates, or nullptr for all of them.
  virtual const std::vector<char>* own_cells() const = 0;
  virtual const LinearSolverStats& stats() const = 0;
};

}  // namespace hencky
