#include "linalg/petsc_solver.hpp"

#include <fmt/format.h>
#include <petscksp.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"
#include "parallel/mpi.hpp"

namespace hencky {
namespace {

using par::check_petsc;

/// The option names of a PETSc option string ("-ksp_type cg -ksp_rtol 1e-8" → -ksp_type,
/// -ksp_rtol).
std::vector<std::string> petsc_option_names(const std::string& options) {
  std::vector<std::string> names;
  std::istringstream in(options);
  std::string word;
  while (in >> word)
    if (par::is_petsc_option_name(word)) names.push_back(word);
  return names;
}

}  // namespace

struct PetscSolver::Impl {
  const Mesh* mesh = nullptr;
  const DofMap* dofs = nullptr;
  int k = 3;                        ///< dofs per node (DofMap::per_node): the block size
  std::vector<PetscInt> first_row;  ///< k × new index of each node: its first global row
  std::vector<int> owned;           ///< this rank's nodes, in the order of their rows
  Mat A = nullptr;
  Mat elements = nullptr;  ///< keep_elements(): the elements' part of A
  Vec b = nullptr, x = nullptr, r = nullptr, x_all = nullptr;
  bool preonly = false;  ///< the KSP applies the preconditioner once (a direct solve)
  bool fixed_rtol = true;  ///< set_relative_tolerance does nothing (direct, or -ksp_rtol given)
  PetscReal rtol_floor = 0, rtol_now = 0;
  VecScatter to_all = nullptr;
  KSP ksp = nullptr;
  bool assembled_once = false;
  bool pending = false;  ///< values set since the matrix was last finished
  /// One process: the cells' matrices go straight into the matrix's value array, colour by
  /// colour in parallel (assemble_local), which needs its rows' columns (PETSc's CSR arrays,
  /// MatGetRowIJ, valid while the pattern stays).
  bool local = false;
  const PetscInt* row_ptr = nullptr;
  const PetscInt* col = nullptr;

  std::vector<std::string> option_names;  ///< the options this solver added: given, defaults
  std::size_t given_options = 0;          ///< how many of them were given

  ~Impl() {
    if (!par::started()) return;  // PETSc already finalized at exit: nothing left to free
    // The options were this run's: the next solver of the process (a test program runs many)
    // starts from PETSc's own defaults again.
    for (const auto& name : option_names) PetscOptionsClearValue(nullptr, name.c_str());
    if (to_all) VecScatterDestroy(&to_all);
    if (x_all) VecDestroy(&x_all);
    if (b) VecDestroy(&b);
    if (x) VecDestroy(&x);
    if (r) VecDestroy(&r);
    if (A) MatDestroy(&A);
    if (elements) MatDestroy(&elements);
    if (ksp) KSPDestroy(&ksp);
  }

  PetscInt row(int node, int d) const {
    return (*dofs).eq[k * node + d] < 0 ? -1 : first_row[node] + d;
  }

  /// The rows of one process's matrix in CSR (columns sorted). Rows are numbered k × node + d
  /// (first_row[n] = k n).
  void local_pattern(std::vector<PetscInt>& row_ptr, std::vector<PetscInt>& col) const {
    const int n_nodes = mesh->n_nodes();
    const std::vector<std::vector<int>> neighbours = node_neighbours(mesh->cells, n_nodes);
    row_ptr.assign(static_cast<std::size_t>(k) * n_nodes + 1, 0);
    for (int v = 0; v < n_nodes; ++v)
      for (int d = 0; d < k; ++d) {
        PetscInt count = 1;  // a prescribed dof: its diagonal
        if (dofs->eq[k * v + d] >= 0) {
          count = 0;
          for (int w : neighbours[v])
            for (int e = 0; e < k; ++e) count += dofs->eq[k * w + e] >= 0;
        }
        row_ptr[k * v + d + 1] = row_ptr[k * v + d] + count;
      }
    col.resize(row_ptr.back());
    for (int v = 0; v < n_nodes; ++v)
      for (int d = 0; d < k; ++d) {
        PetscInt* c = col.data() + row_ptr[k * v + d];
        if (dofs->eq[k * v + d] < 0) {
          *c = k * v + d;
          continue;
        }
        for (int w : neighbours[v])
          for (int e = 0; e < k; ++e)
            if (dofs->eq[k * w + e] >= 0) *c++ = k * w + e;
      }
  }

  /// Position of entry (r, c) in the value array of one process's matrix.
  PetscInt position(PetscInt r, PetscInt c) const {
    return static_cast<PetscInt>(std::lower_bound(col + row_ptr[r], col + row_ptr[r + 1], c) - col);
  }

  // The constructor's steps, in its order.
  void add_options(const std::string& options);
  void number_rows(const Partition& partition, const std::optional<PetscPart>& part);
  void create_matrix(const Partition& partition, const std::optional<PetscPart>& part);
  void preallocate_blocks(const Partition& partition, const std::optional<PetscPart>& part);
  void set_rigid_body_modes();
  std::string create_ksp(PetscPreset preset, const std::string& options, double tolerance);
};

/// Puts the options in force, and the GAMG defaults hencky prefers where they were not given;
/// keeps the names, to clear them when the solver goes.
void PetscSolver::Impl::add_options(const std::string& options) {
  par::add_petsc_options(options);
  option_names = petsc_option_names(options);
  given_options = option_names.size();
  // GAMG (preset or chosen by an option): Chebyshev smoothing needs an upper bound of each
  // level's spectrum. GAMG's own estimate (from its prolongator smoothing) fell short on a
  // contact problem (CG stopped on DIVERGED_INDEFINITE_PC once the contact had released); a CG
  // estimate per level does not (PETSc's manual recommends CG for SPD operators). Options
  // given win.
  for (const auto& [name, value] : {std::pair{"-pc_gamg_use_sa_esteig", "0"},
                                    std::pair{"-mg_levels_esteig_ksp_type", "cg"}}) {
    PetscBool given = PETSC_FALSE;
    check_petsc(PetscOptionsHasName(nullptr, nullptr, name, &given), "PetscOptionsHasName");
    if (given) continue;
    check_petsc(PetscOptionsSetValue(nullptr, name, value), "PetscOptionsSetValue");
    option_names.push_back(name);
  }
}

/// first_row and owned: rows by rank, then by the node's own order within the rank.
void PetscSolver::Impl::number_rows(const Partition& partition,
                                    const std::optional<PetscPart>& part) {
  const int n_nodes = mesh->n_nodes(), parts = partition.parts, me = partition.rank;
  first_row.resize(n_nodes);
  if (part) {
    // A part: its own nodes are its first ones; a ghost's rows are its owner's numbering of
    // it, after the nodes of the ranks before that owner.
    const MeshPart& p = part->part;
    const std::vector<long long> before = par::rank_offsets(p.owned_nodes);
    for (int n = 0; n < n_nodes; ++n)
      first_row[n] = k * static_cast<PetscInt>(before[p.node_owner[n]] + p.owner_index[n]);
    for (int n = 0; n < p.owned_nodes; ++n) owned.push_back(n);
  } else {
    std::vector<PetscInt> count(parts + 1, 0);
    for (int n = 0; n < n_nodes; ++n) ++count[partition.node_owner[n] + 1];
    for (int r = 0; r < parts; ++r) count[r + 1] += count[r];
    for (int n = 0; n < n_nodes; ++n) {
      const int r = partition.node_owner[n];
      first_row[n] = k * count[r]++;
      if (r == me) owned.push_back(n);
    }
  }
}

/// A, preallocated, and the vectors of its rows.
void PetscSolver::Impl::create_matrix(const Partition& partition,
                                      const std::optional<PetscPart>& part) {
  const PetscInt n_local = k * static_cast<PetscInt>(owned.size());
  check_petsc(MatCreate(PETSC_COMM_WORLD, &A), "MatCreate");
  check_petsc(MatSetSizes(A, n_local, n_local, PETSC_DETERMINE, PETSC_DETERMINE), "MatSetSizes");
  check_petsc(MatSetBlockSize(A, k), "MatSetBlockSize");
  if (partition.parts == 1) {
    // The exact pattern: a free dof couples to the free dofs of its node's neighbours, a
    // prescribed one to itself (its identity row); PETSc keeps it as given (columns sorted).
    check_petsc(MatSetType(A, MATSEQAIJ), "MatSetType");
    std::vector<PetscInt> row_ptr, col;
    local_pattern(row_ptr, col);
    check_petsc(MatSeqAIJSetPreallocationCSR(A, row_ptr.data(), col.data(), nullptr),
                "matrix preallocation");
    local = true;
  } else {
    preallocate_blocks(partition, part);
  }
  check_petsc(MatSetOption(A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE), "MatSetOption");
  check_petsc(MatSetOption(A, MAT_SYMMETRIC, PETSC_TRUE), "MatSetOption");
  check_petsc(MatSetOption(A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE), "MatSetOption");
  check_petsc(MatCreateVecs(A, &x, &b), "MatCreateVecs");
  check_petsc(VecDuplicate(b, &r), "VecDuplicate");
  // A replicated mesh takes the whole solution on every rank; a part, its own nodes' and its
  // ghosts' through the exchange (solve).
  if (!part) check_petsc(VecScatterCreateToAll(x, &to_all, &x_all), "VecScatterCreateToAll");
}

/// Several processes: A as MATAIJ, preallocated per block row with the nodes coupled to each
/// owned node through its cells.
void PetscSolver::Impl::preallocate_blocks(const Partition& partition,
                                           const std::optional<PetscPart>& part) {
  const int n_nodes = mesh->n_nodes(), me = partition.rank;
  std::vector<int> ptr, idx;
  node_cell_incidence(mesh->cells, n_nodes, ptr, idx);
  std::vector<PetscInt> d_nnz(owned.size()), o_nnz(owned.size());
  std::vector<int> seen(n_nodes, -1);
  if (part) {
    // A part sees a node's couplings through its own cells only: each rank counts those of
    // its copy of every node (columns of the row's owner in the diagonal block), and the
    // owner adds the copies' counts up. A coupling two ranks' cells share is counted by
    // both: the preallocation may exceed the row, never fall short.
    std::vector<double> counts(2 * static_cast<std::size_t>(n_nodes), 0.0);
    for (int n = 0; n < n_nodes; ++n) {
      const int owner = part->part.node_owner[n];
      for (int c = ptr[n]; c < ptr[n + 1]; ++c)
        for (int m : mesh->cells.nodes(idx[c])) {
          if (seen[m] == n) continue;
          seen[m] = n;
          counts[2 * n + (part->part.node_owner[m] == owner ? 0 : 1)] += 1;
        }
    }
    part->exchange.sum(counts, 2);
    const PetscInt own_blocks = static_cast<PetscInt>(owned.size());
    PetscInt all_blocks = own_blocks;
    {
      double total = static_cast<double>(own_blocks);
      par::sum_in_place(std::span<double>(&total, 1));
      all_blocks = static_cast<PetscInt>(total);
    }
    for (std::size_t l = 0; l < owned.size(); ++l) {
      d_nnz[l] = std::clamp<PetscInt>(static_cast<PetscInt>(counts[2 * l]), 1, own_blocks);
      o_nnz[l] =
          std::min<PetscInt>(static_cast<PetscInt>(counts[2 * l + 1]), all_blocks - own_blocks);
    }
  } else {
    for (std::size_t l = 0; l < owned.size(); ++l) {
      const int n = owned[l];
      PetscInt d = 0, o = 0;
      for (int c = ptr[n]; c < ptr[n + 1]; ++c)
        for (int m : mesh->cells.nodes(idx[c])) {
          if (seen[m] == static_cast<int>(l)) continue;
          seen[m] = static_cast<int>(l);
          (partition.node_owner[m] == me ? d : o) += 1;
        }
      d_nnz[l] = std::max<PetscInt>(d, 1);
      o_nnz[l] = o;
    }
  }
  check_petsc(MatSetType(A, MATAIJ), "MatSetType");
  check_petsc(MatXAIJSetPreallocation(A, k, d_nnz.data(), o_nnz.data(), nullptr, nullptr),
              "matrix preallocation");
}

/// Near null space of the displacement: the six rigid-body modes of the owned nodes'
/// coordinates (a scalar field's, the constants, is GAMG's default).
void PetscSolver::Impl::set_rigid_body_modes() {
  Vec coords = nullptr;
  check_petsc(VecDuplicate(x, &coords), "VecDuplicate");
  check_petsc(VecSetBlockSize(coords, 3), "VecSetBlockSize");
  PetscScalar* c = nullptr;
  check_petsc(VecGetArray(coords, &c), "VecGetArray");
  for (std::size_t l = 0; l < owned.size(); ++l)
    for (int d = 0; d < 3; ++d) c[3 * l + d] = mesh->x[owned[l]][d];
  check_petsc(VecRestoreArray(coords, &c), "VecRestoreArray");
  MatNullSpace rigid = nullptr;
  check_petsc(MatNullSpaceCreateRigidBody(coords, &rigid), "MatNullSpaceCreateRigidBody");
  check_petsc(MatSetNearNullSpace(A, rigid), "MatSetNearNullSpace");
  MatNullSpaceDestroy(&rigid);
  VecDestroy(&coords);
}

/// The KSP of the preset with the options in force; returns the method it ended up with
/// ("PETSc cg + gamg"). std::invalid_argument when PETSc refuses the options.
std::string PetscSolver::Impl::create_ksp(PetscPreset preset, const std::string& options,
                                          double tolerance) {
  check_petsc(KSPCreate(PETSC_COMM_WORLD, &ksp), "KSPCreate");
  PC pc = nullptr;
  check_petsc(KSPGetPC(ksp, &pc), "KSPGetPC");
  if (preset == PetscPreset::gamg) {
    check_petsc(KSPSetType(ksp, KSPCG), "KSPSetType");
    check_petsc(PCSetType(pc, PCGAMG), "PCSetType");
    // CG stops on the true residual ‖b − Ax‖ (PETSc's default for CG is the preconditioned
    // one): the step loop's tolerance for a solve (set_relative_tolerance) is a fraction of
    // the true residual, and the preconditioned norm can differ from it by orders.
    check_petsc(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
  } else {
    check_petsc(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
    check_petsc(PCSetType(pc, PCCHOLESKY), "PCSetType");
    check_petsc(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  }
  check_petsc(KSPSetTolerances(ksp, tolerance, PETSC_DEFAULT, PETSC_DEFAULT, 10000),
              "KSPSetTolerances");
  if (const PetscErrorCode e = KSPSetFromOptions(ksp))
    throw std::invalid_argument(fmt::format("PETSc refused the solver options \"{}\": {}",
                                            options, par::petsc_message(e)));
  KSPType kt = nullptr;
  PCType pt = nullptr;
  KSPGetType(ksp, &kt);
  PCGetType(pc, &pt);
  preonly = std::string(kt) == KSPPREONLY;
  PetscBool rtol_given = PETSC_FALSE;
  check_petsc(PetscOptionsHasName(nullptr, nullptr, "-ksp_rtol", &rtol_given),
              "PetscOptionsHasName");
  fixed_rtol = preonly || rtol_given;
  check_petsc(KSPGetTolerances(ksp, &rtol_floor, nullptr, nullptr, nullptr), "KSPGetTolerances");
  rtol_now = rtol_floor;
  std::string method = fmt::format("PETSc {} + {}", kt, pt);
  MatSolverType st = nullptr;
  if (PCFactorGetMatSolverType(pc, &st) == 0 && st) method += fmt::format(" ({})", st);
  return method;
}

PetscSolver::PetscSolver(const Mesh& mesh, const DofMap& dofs, const Assembler& assembler,
                         Partition partition, PetscPreset preset, const std::string& options,
                         double tolerance, std::optional<PetscPart> part)
    : impl_(std::make_unique<Impl>()),
      assembler_(assembler),
      partition_(std::move(partition)),
      part_(part) {
  par::ensure_petsc();
  Impl& s = *impl_;
  s.add_options(options);
  s.mesh = &mesh;
  s.dofs = &dofs;
  s.k = dofs.per_node;
  s.number_rows(partition_, part_);
  s.create_matrix(partition_, part_);
  if (s.k == 3) s.set_rigid_body_modes();
  const std::string method = s.create_ksp(preset, options, tolerance);
  const int parts = partition_.parts;
  stats_.description = fmt::format("{}, {} rank{}", method, parts, parts > 1 ? "s" : "");
}

PetscSolver::~PetscSolver() = default;

std::vector<std::string> PetscSolver::unused_options() const {
  std::vector<std::string> out;
  for (std::size_t k = 0; k < impl_->given_options; ++k) {
    const std::string& name = impl_->option_names[k];
    PetscBool used = PETSC_FALSE;  // the database keeps names without their '-'
    if (PetscOptionsUsed(nullptr, name.c_str() + 1, &used) == 0 && !used) out.push_back(name);
  }
  return out;
}

void PetscSolver::set_relative_tolerance(double rtol) {
  Impl& s = *impl_;
  if (s.fixed_rtol) return;
  const PetscReal r = forcing_tolerance(rtol, s.rtol_floor);
  if (r == s.rtol_now) return;
  s.rtol_now = r;
  check_petsc(KSPSetTolerances(s.ksp, r, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT),
              "KSPSetTolerances");
}

void PetscSolver::assemble_cells(const CellMatrix& cell_matrix) {
  Impl& s = *impl_;
  // A matrix assembled and then not used (a Newton iteration that converged on it) is finished
  // first: PETSc zeroes finished matrices only.
  if (s.pending) end_matrix();
  if (s.local) {
    assemble_local(cell_matrix);
    return;
  }
  if (s.assembled_once) check_petsc(MatZeroEntries(s.A), "MatZeroEntries");
  s.pending = true;
  for (std::size_t l = 0; l < s.owned.size(); ++l)
    for (int d = 0; d < s.k; ++d)
      if (s.dofs->eq[s.k * s.owned[l] + d] < 0) {
        const PetscInt r = s.first_row[s.owned[l]] + d;
        check_petsc(MatSetValue(s.A, r, r, 1.0, ADD_VALUES), "MatSetValue");
      }
  const CellSet& cells = s.mesh->cells;
  std::string failure;
  assembler_.matrices(
      cell_matrix,
      [&](int e, const double* ke) {
        // MatSetValues is not thread-safe; the cells' matrices are computed in parallel.
#pragma omp critical(hencky_petsc_add)
        try {
          if (failure.empty()) {
            const auto nodes = cells.nodes(e);
            PetscInt rows[3 * max_cell_nodes];
            const PetscInt nd = s.k * static_cast<PetscInt>(nodes.size());
            for (std::size_t a = 0; a < nodes.size(); ++a)
              for (int d = 0; d < s.k; ++d) rows[s.k * a + d] = s.row(nodes[a], d);
            check_petsc(MatSetValues(s.A, nd, rows, nd, rows, ke, ADD_VALUES), "MatSetValues");
          }
        } catch (const std::exception& x) {
          failure = x.what();
        }
      },
      own_cells());
  if (!failure.empty()) throw std::runtime_error(failure);
}

void PetscSolver::assemble_local(const CellMatrix& cell_matrix) {
  Impl& s = *impl_;
  PetscInt n = 0;
  PetscBool done = PETSC_FALSE;
  check_petsc(MatGetRowIJ(s.A, 0, PETSC_FALSE, PETSC_FALSE, &n, &s.row_ptr, &s.col, &done),
              "MatGetRowIJ");
  if (!done) throw std::runtime_error("PETSc did not give the matrix's rows (MatGetRowIJ)");
  PetscScalar* a = nullptr;
  check_petsc(MatSeqAIJGetArray(s.A, &a), "MatSeqAIJGetArray");
  std::fill(a, a + s.row_ptr[n], 0.0);
  const int n_nodes = s.mesh->n_nodes();
  for (int v = 0; v < n_nodes; ++v)
    for (int d = 0; d < s.k; ++d)
      if (s.dofs->eq[s.k * v + d] < 0) a[s.row_ptr[s.k * v + d]] = 1.0;
  // Cells of one colour share no node, hence no row: the threads write disjoint entries.
  const CellSet& cells = s.mesh->cells;
  assembler_.matrices(cell_matrix, [&](int e, const double* ke) {
    const auto nodes = cells.nodes(e);
    PetscInt rows[3 * max_cell_nodes];
    const int nd = s.k * static_cast<int>(nodes.size());
    for (std::size_t n = 0; n < nodes.size(); ++n)
      for (int d = 0; d < s.k; ++d) rows[s.k * n + d] = s.row(nodes[n], d);
    for (int i = 0; i < nd; ++i) {
      if (rows[i] < 0) continue;
      for (int j = 0; j < nd; ++j)
        if (rows[j] >= 0) a[s.position(rows[i], rows[j])] += ke[i * nd + j];
    }
  });
  // Restoring the array marks the matrix as changed: the preconditioner is set up again.
  check_petsc(MatSeqAIJRestoreArray(s.A, &a), "MatSeqAIJRestoreArray");
  check_petsc(MatRestoreRowIJ(s.A, 0, PETSC_FALSE, PETSC_FALSE, &n, &s.row_ptr, &s.col, &done),
              "MatRestoreRowIJ");
  s.assembled_once = true;
}

void PetscSolver::add_block(int a, int b, const Mat3& block) {  // displacement only (k == 3)
  // The whole mesh on every rank: the owner of the rows adds the block. A distributed mesh's
  // caller gives each block once, from the rank that holds its contact point (the rows may be
  // another rank's: PETSc sends them there at the assembly).
  if (!part_ && partition_.node_owner[a] != partition_.rank) return;
  const Impl& s = *impl_;
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> rows = block;
  PetscInt r[3], c[3];
  for (int d = 0; d < 3; ++d) r[d] = s.row(a, d), c[d] = s.row(b, d);
  check_petsc(MatSetValues(s.A, 3, r, 3, c, rows.data(), ADD_VALUES), "MatSetValues");
}

void PetscSolver::end_matrix() {
  Impl& s = *impl_;
  check_petsc(MatAssemblyBegin(s.A, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  check_petsc(MatAssemblyEnd(s.A, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  s.assembled_once = true;
  s.pending = false;
}

void PetscSolver::keep_cells() {
  end_matrix();
  Impl& s = *impl_;
  if (!s.elements)
    check_petsc(MatDuplicate(s.A, MAT_COPY_VALUES, &s.elements), "MatDuplicate");
  else
    check_petsc(MatCopy(s.A, s.elements, SAME_NONZERO_PATTERN), "MatCopy");
}

bool PetscSolver::restore_cells() {
  Impl& s = *impl_;
  if (!s.elements) return false;
  check_petsc(MatCopy(s.elements, s.A, SAME_NONZERO_PATTERN), "MatCopy");
  return true;
}

void PetscSolver::factorize() {
  end_matrix();
  Impl& s = *impl_;
  check_petsc(KSPSetOperators(s.ksp, s.A, s.A), "KSPSetOperators");
  if (const PetscErrorCode e = KSPSetUp(s.ksp)) {
    const std::string what =
        fmt::format("{}: set-up failed: {}", stats_.description, par::petsc_message(e));
    // Errors of the options (an algorithm that does not exist or does not apply to this
    // matrix type), as opposed to numerical ones (a zero pivot, an indefinite matrix).
    switch (e) {
      case PETSC_ERR_SUP:
      case PETSC_ERR_ARG_WRONG:
      case PETSC_ERR_ARG_OUTOFRANGE:
      case PETSC_ERR_ARG_INCOMP:
      case PETSC_ERR_ARG_UNKNOWN_TYPE:
      case PETSC_ERR_USER_INPUT:
      case PETSC_ERR_USER:  // an option's value it does not know ("-matptap_via allatonce")
        throw SolverOptionsError(what);
      default:
        throw LinearSystemError(LinearSystemError::Kind::not_positive_definite, what);
    }
  }
  ++stats_.n_factorizations;
  MatInfo info;
  if (MatGetInfo(s.A, MAT_GLOBAL_SUM, &info) == 0) stats_.matrix_nnz = info.nz_used;
}

void PetscSolver::solve(std::span<const double> rhs, std::span<double> x) {
  Impl& s = *impl_;
  const auto& eq = s.dofs->eq;
  PetscScalar* b = nullptr;
  check_petsc(VecGetArray(s.b, &b), "VecGetArray");
  for (std::size_t l = 0; l < s.owned.size(); ++l)
    for (int d = 0; d < s.k; ++d) {
      const int k = eq[s.k * s.owned[l] + d];
      b[s.k * l + d] = k >= 0 ? rhs[k] : 0.0;
    }
  check_petsc(VecRestoreArray(s.b, &b), "VecRestoreArray");
  check_petsc(KSPSolve(s.ksp, s.b, s.x), "KSPSolve");
  KSPConvergedReason reason;
  PetscInt its = 0;
  KSPGetConvergedReason(s.ksp, &reason);
  KSPGetIterationNumber(s.ksp, &its);
  ++stats_.n_solves;
  stats_.iterations += its;
  if (reason < 0) {
    PC pc = nullptr;
    PCFailedReason pcr = PC_NOERROR;
    KSPGetPC(s.ksp, &pc);
    PCGetFailedReasonRank(pc, &pcr);
    std::string why = KSPConvergedReasons[reason];
    if (reason == KSP_DIVERGED_PC_FAILED) why += fmt::format(" ({})", PCFailedReasons[pcr]);
    throw LinearSystemError(LinearSystemError::Kind::diverged,
                            fmt::format("{} did not solve the linear system: {} after {} iterations",
                                        stats_.description, why, its));
  }
  // A direct solve (preonly) reports no residual of its own, and MUMPS factors a singular
  // matrix (a body not held) without complaint: check the true residual.
  if (s.preonly) {
    PetscReal b_norm = 0, r_norm = 0;
    check_petsc(MatMult(s.A, s.x, s.r), "MatMult");
    check_petsc(VecAYPX(s.r, -1.0, s.b), "VecAYPX");
    check_petsc(VecNorm(s.b, NORM_2, &b_norm), "VecNorm");
    check_petsc(VecNorm(s.r, NORM_2, &r_norm), "VecNorm");
    if (!(r_norm <= 1e-8 * b_norm))
      throw LinearSystemError(
          LinearSystemError::Kind::singular,
          fmt::format("{}: the solution leaves a relative residual of {:.2e}: the matrix is "
                      "singular or nearly so",
                      stats_.description, b_norm > 0 ? r_norm / b_norm : r_norm));
  }
  if (part_) {
    // The own nodes' values, then the ghosts' from their owners.
    std::vector<double> nodal(static_cast<std::size_t>(s.k) * s.mesh->n_nodes(), 0.0);
    const PetscScalar* own = nullptr;
    check_petsc(VecGetArrayRead(s.x, &own), "VecGetArrayRead");
    std::copy(own, own + s.k * s.owned.size(), nodal.begin());
    check_petsc(VecRestoreArrayRead(s.x, &own), "VecRestoreArrayRead");
    part_->exchange.to_ghosts(nodal, s.k);
    for (std::size_t i = 0; i < nodal.size(); ++i)
      if (const int k = eq[i]; k >= 0) x[k] = nodal[i];
    return;
  }
  check_petsc(VecScatterBegin(s.to_all, s.x, s.x_all, INSERT_VALUES, SCATTER_FORWARD), "VecScatter");
  check_petsc(VecScatterEnd(s.to_all, s.x, s.x_all, INSERT_VALUES, SCATTER_FORWARD), "VecScatter");
  const PetscScalar* all = nullptr;
  check_petsc(VecGetArrayRead(s.x_all, &all), "VecGetArrayRead");
  for (int n = 0; n < s.mesh->n_nodes(); ++n)
    for (int d = 0; d < s.k; ++d)
      if (const int k = eq[s.k * n + d]; k >= 0) x[k] = all[s.first_row[n] + d];
  check_petsc(VecRestoreArrayRead(s.x_all, &all), "VecRestoreArrayRead");
}

}  // namespace hencky
