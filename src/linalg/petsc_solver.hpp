#pragma once
// The PETSc back end (solver.linear: petsc, and every run under mpirun with more than one rank).
// The global matrix is a PETSc MPIAIJ matrix with block size 3 over all nodal dofs, rows split
// by node owner (parallel/partition.hpp). Each rank adds the element matrices of its own cells;
// PETSc moves the entries of shared nodes to their owners. A prescribed dof keeps its row and
// column as the identity, so that every node keeps its three rows and GAMG sees 3x3 blocks; the
// rigid-body modes of the node coordinates are its near null space (PETSc's
// MatNullSpaceCreateRigidBody, as in PETSc's elasticity tutorial ex56).
//
// Default: CG with GAMG ("iterative"), or MUMPS Cholesky ("direct"); any PETSc option given in
// the case (solver.petsc_options) or on the command line overrides it (KSPSetFromOptions).
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "linalg/linear_solver.hpp"
#include "mesh/mesh.hpp"
#include "parallel/partition.hpp"

namespace hencky {

enum class PetscPreset { gamg, mumps };

class PetscSolver final : public LinearSolver {
 public:
  /// Collective. `options` (PETSc options, later ones win) are in force while this solver
  /// lives; std::invalid_argument when PETSc refuses them. `tolerance` is the tightest
  /// relative residual of the Krylov solve (set_relative_tolerance loosens it per solve;
  /// -ksp_rtol fixes it instead).
  PetscSolver(const Mesh& mesh, const DofMap& dofs, Partition partition, PetscPreset preset,
              const std::string& options = "", double tolerance = 1e-10);
  ~PetscSolver() override;

  const Partition& partition() const { return partition_; }
  /// The options given to this solver that PETSc has not read (misspelt, or for a solver not
  /// in use). Meaningful after the first solve: PETSc reads most options at set-up.
  std::vector<std::string> unused_options() const;

  // The matrix, assembled in place (collective: begin_matrix and end_matrix).
  /// Zeroes the matrix and puts 1 on the diagonal of this rank's prescribed dofs.
  void begin_matrix();
  /// Adds a cell's matrix (row-major, 3 dofs per node in the order of `nodes`); rows and
  /// columns of prescribed dofs are skipped. Not thread-safe: one caller at a time.
  void add_cell(std::span<const int> nodes, const double* ke);
  /// Adds a 3x3 block (row-major) coupling the dofs of nodes a (rows) and b (columns).
  void add_block(int a, int b, const double* block);
  /// Finishes the assembly (moves the entries of shared nodes to their owners).
  void end_matrix();
  /// Keeps a copy of the assembled matrix (the elements' part, before the contact's blocks).
  void keep_elements();
  /// Puts the kept copy back as the matrix to add to; false when nothing was kept.
  bool restore_elements();
  /// Sets the preconditioner (or factorization) up for the assembled matrix. Throws SolveError
  /// when PETSc reports a failure (a zero pivot, an indefinite matrix for Cholesky), and
  /// SolverOptionsError when the failure is one of the options (an algorithm that does not
  /// exist or does not apply).
  void set_up();
  /// LinearSolver::set_relative_tolerance for the Krylov solve: no effect on a direct solve
  /// (MUMPS) or when -ksp_rtol was given (the user's tolerance stands).
  void set_relative_tolerance(double rtol) override;

  // LinearSolver: the pattern interface of the serial back ends is not used here.
  void analyze(const SymmetricPattern&) override;
  void factorize(std::span<const double>) override;
  /// rhs and x are the free dofs, full length on every rank (DofMap numbering). Collective.
  void solve(std::span<const double> rhs, std::span<double> x) override;
  const LinearSolverStats& stats() const override { return stats_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Partition partition_;
  LinearSolverStats stats_;
};

}  // namespace hencky
