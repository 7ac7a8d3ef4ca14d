#pragma once
// The PETSc back end (solver.linear: petsc, and every run under mpirun with more than one rank).
// The global matrix is a PETSc MPIAIJ matrix over all nodal dofs with the DofMap's dofs per
// node as block size (3 for the displacement, 1 for the temperature), rows split by node owner
// (parallel/partition.hpp). Each rank adds the element matrices of its own cells; PETSc moves
// the entries of shared nodes to their owners. A prescribed dof keeps its row and column as the
// identity, so that every node keeps its rows and GAMG sees whole blocks; for the displacement,
// the rigid-body modes of the node coordinates are its near null space (PETSc's
// MatNullSpaceCreateRigidBody, as in PETSc's elasticity tutorial ex56).
//
// Default: CG with GAMG ("iterative"), or MUMPS Cholesky ("direct"); any PETSc option given in
// the case (solver.petsc_options) or on the command line overrides it (KSPSetFromOptions).
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "linalg/linear_system.hpp"
#include "mesh/mesh.hpp"
#include "parallel/mesh_part.hpp"
#include "parallel/node_exchange.hpp"
#include "parallel/partition.hpp"

namespace hencky {

enum class PetscPreset { gamg, mumps };

/// A rank's part of a distributed mesh (issue 21): the mesh given to PetscSolver is the part
/// (`part`'s numbering against the whole, whose own `mesh` is not read), a node's rows are
/// numbered by its owner (owners in rank order, each rank's own nodes in their local order),
/// and a solution reaches the ghost nodes through `exchange`.
struct PetscPart {
  const MeshPart& part;
  const NodeExchange& exchange;
};

class PetscSolver final : public LinearSystem {
 public:
  /// Collective. `options` (PETSc options, later ones win) are in force while this solver
  /// lives; std::invalid_argument when PETSc refuses them. `tolerance` is the tightest
  /// relative residual of the Krylov solve (set_relative_tolerance loosens it per solve;
  /// -ksp_rtol fixes it instead). `assembler` gives the cells' matrices (its pattern is not
  /// used).
  PetscSolver(const Mesh& mesh, const DofMap& dofs, const Assembler& assembler, Partition partition,
              PetscPreset preset, const std::string& options = "", double tolerance = 1e-10,
              std::optional<PetscPart> part = std::nullopt);
  ~PetscSolver() override;

  const Partition& partition() const { return partition_; }

  // LinearSystem. The matrix is assembled in place: assemble_cells zeroes it, puts 1 on the
  // diagonal of this rank's prescribed dofs and adds this rank's cells; PETSc moves the
  // entries of shared nodes to their owners when the matrix is finished (keep_cells,
  // factorize). add_block adds the blocks of the rows this rank owns (on a distributed mesh,
  // every block it is given).
  void assemble_cells(const CellMatrix& cell_matrix) override;
  void keep_cells() override;
  bool restore_cells() override;
  void add_block(int a, int b, const Mat3& block) override;
  /// Sets the preconditioner (or factorization) up for the assembled matrix. Throws
  /// LinearSystemError when PETSc reports a numerical failure (a zero pivot, an indefinite
  /// matrix for Cholesky), and SolverOptionsError when the failure is one of the options (an
  /// algorithm that does not exist or does not apply).
  void factorize() override;
  /// rhs and x are the free dofs, full length on every rank (DofMap numbering). Collective.
  void solve(std::span<const double> rhs, std::span<double> x) override;
  /// For the Krylov solve: no effect on a direct solve (MUMPS) or when -ksp_rtol was given
  /// (the user's tolerance stands).
  void set_relative_tolerance(double rtol) override;
  std::vector<std::string> unused_options() const override;
  /// A part's cells are all its own (nullptr); a replicated mesh's, the partition's.
  const std::vector<char>* own_cells() const override {
    return partition_.parts > 1 && !part_ ? &partition_.owned_cell : nullptr;
  }
  const LinearSolverStats& stats() const override { return stats_; }

 private:
  void end_matrix();
  /// assemble_cells in one process: straight into the matrix's values, no PETSc call per cell.
  void assemble_local(const CellMatrix& cell_matrix);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  const Assembler& assembler_;
  Partition partition_;
  std::optional<PetscPart> part_;
  LinearSolverStats stats_;
};

}  // namespace hencky
