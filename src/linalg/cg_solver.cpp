// Preconditioned conjugate gradients (Eigen) with an incomplete Cholesky preconditioner, for
// problems whose factor does not fit in memory. The preconditioner is rebuilt when the matrix
// changes, as a factorization would be.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <fmt/format.h>

#include "core/error.hpp"
#include "linalg/sparse_solver.hpp"

namespace hencky {
namespace {

class CgSolver final : public SparseSolver {
  // Eigen's incomplete Cholesky needs 32-bit indices: the CSC arrays are copied once per matrix.
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  using Map = Eigen::Map<const Eigen::SparseMatrix<double, Eigen::ColMajor, std::int64_t>>;

 public:
  explicit CgSolver(double tolerance) : tolerance_(tolerance) {
    cg_.setTolerance(tolerance_);
    stats_.description = "conjugate gradients, incomplete Cholesky preconditioner (Eigen)";
  }
  void analyze(const SymmetricPattern& p, std::span<const std::int64_t> /*ordering*/) override {
    pattern_ = &p;
    ++stats_.n_analyses;
  }
  void factorize(std::span<const double> values) override {
    const Map a(pattern_->n, pattern_->n, pattern_->nnz(), pattern_->col_ptr.data(),
                pattern_->row.data(), values.data());
    matrix_ = a.cast<double>();  // IncompleteCholesky and CG keep references into the matrix they are given
    cg_.setMaxIterations(std::max<std::int64_t>(1000, 10 * pattern_->n));
    cg_.compute(matrix_);
    if (cg_.info() != Eigen::Success)
      throw LinearSystemError(
          LinearSystemError::Kind::not_positive_definite,
          "incomplete Cholesky preconditioner failed (matrix not positive definite?)");
    ++stats_.n_factorizations;
  }
  void solve(std::span<const double> rhs, std::span<double> x) override {
    Eigen::Map<const Eigen::VectorXd> b(rhs.data(), static_cast<Eigen::Index>(rhs.size()));
    Eigen::Map<Eigen::VectorXd> xv(x.data(), static_cast<Eigen::Index>(x.size()));
    xv = cg_.solve(b);
    stats_.iterations += cg_.iterations();
    ++stats_.n_solves;
    if (cg_.info() != Eigen::Success || !xv.allFinite())
      throw LinearSystemError(LinearSystemError::Kind::diverged,
                              fmt::format("conjugate gradients did not converge: relative residual {:.2e} "
                                   "after {} iterations",
                                   cg_.error(), cg_.iterations()));
  }
  const LinearSolverStats& stats() const override { return stats_; }
  void set_relative_tolerance(double rtol) override {
    // Eigen's CG measures the true residual ‖b − Ax‖ / ‖b‖, as the forcing term needs.
    cg_.setTolerance(forcing_tolerance(rtol, tolerance_));
  }

 private:
  double tolerance_;
  const SymmetricPattern* pattern_ = nullptr;
  Matrix matrix_;
  Eigen::ConjugateGradient<Matrix, Eigen::Upper, Eigen::IncompleteCholesky<double, Eigen::Upper>> cg_;
  LinearSolverStats stats_;
};

}  // namespace

std::unique_ptr<SparseSolver> make_cholmod_solver();

std::unique_ptr<SparseSolver> make_sparse_solver(LinearSolverKind kind, double tolerance) {
  if (kind == LinearSolverKind::iterative) return std::make_unique<CgSolver>(tolerance);
  return make_cholmod_solver();
}

}  // namespace hencky
