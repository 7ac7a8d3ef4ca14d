#pragma once
// Anderson acceleration of a fixed-point iteration (solver.acceleration).
//
// The fixed-matrix schemes iterate x_{k+1} = G(x_k) = x_k + f(x_k) with one factorization: a
// fixed-point iteration that contracts linearly, slowly where the plastic zone's stiffness is
// far from the matrix's. Anderson's method (D. G. Anderson, J. ACM 12, 1965; in the form of
// H. F. Walker and P. Ni, SIAM J. Numer. Anal. 49, 2011) takes the next iterate as the
// combination of the last m + 1 iterates whose corrections f_k best cancel:
//   γ = argmin ‖f_k − ΔF γ‖_W,  x_{k+1} = x_k + f_k − (ΔX + ΔF) γ,
// with ΔX, ΔF the differences of the last m iterates and corrections. It costs m vectors and a
// small least-squares problem per iteration, no factorization, and is a secant (multisecant
// quasi-Newton) method built on the scheme's own iteration: the fixed point, and so the answer,
// is the scheme's.
//
// The norm ‖·‖_W weighs the rows: the initial-stress schemes iterate on the displacements (all
// rows weigh 1); the initial-strain schemes on their initial strains at the points, and the
// displacements follow them (weight 0: x + f of every iterate is the displacement of the plain
// update, so the mixed displacement is the same combination, docs/schemes.md). The weighted
// least squares is solved through its m × m normal equations, so that rows held by different
// MPI ranks enter through one sum (`reduce`).
#include <Eigen/Dense>
#include <algorithm>
#include <functional>
#include <span>
#include <vector>

namespace hencky {

class Anderson {
 public:
  explicit Anderson(int depth) : depth_(depth) {}

  /// Forgets the history: the next step is the plain one (after the map G changed: a new
  /// matrix, a new step, a new contact set, or a step that made things worse).
  void reset() {
    stored_ = next_ = 0;
    have_prev_ = false;
  }

  /// `x`: the current iterate; `f`: its plain correction G(x) − x, replaced by the accelerated
  /// one. `w`: the rows' weights in the least squares (x.size() of them). `reduce`: sums its
  /// argument over the ranks when the weighted rows are spread over them (empty: one rank, or
  /// rows that every rank holds whole). The history is kept as columns of two n × depth
  /// matrices, the oldest column overwritten when they are full (the least-squares weights do
  /// not depend on the order of the columns): after the first iterations nothing is allocated.
  void accelerate(const std::vector<double>& x, std::vector<double>& f,
                  const std::vector<double>& w,
                  const std::function<void(std::span<double>)>& reduce = {}) {
    const Eigen::Index n = static_cast<Eigen::Index>(x.size());
    const Eigen::Map<const Eigen::VectorXd> xk(x.data(), n), wk(w.data(), n);
    Eigen::Map<Eigen::VectorXd> fk(f.data(), n);
    if (dx_.rows() != n) {
      dx_.resize(n, depth_);
      df_.resize(n, depth_);
      reset();
    }
    if (have_prev_) {
      const Eigen::Index col = next_ % depth_;
      dx_.col(col) = xk - x_prev_;
      df_.col(col) = fk - f_prev_;
      next_ = col + 1;
      stored_ = std::min<Eigen::Index>(stored_ + 1, depth_);
    }
    x_prev_ = xk;
    f_prev_ = fk;
    have_prev_ = true;
    if (stored_ == 0) return;
    // Normal equations ΔFᵀWΔF γ = ΔFᵀW f, summed over the ranks in one message.
    const auto df = df_.leftCols(stored_);
    const Eigen::Index m = stored_;
    buffer_.resize(m * m + m);
    Eigen::Map<Eigen::MatrixXd> gram(buffer_.data(), m, m);
    Eigen::Map<Eigen::VectorXd> rhs(buffer_.data() + m * m, m);
    wdf_ = wk.asDiagonal() * df;
    gram.noalias() = df.transpose() * wdf_;
    rhs.noalias() = wdf_.transpose() * fk;
    if (reduce) reduce(std::span<double>(buffer_.data(), buffer_.size()));
    // Columns that are (nearly) dependent carry no information: the decomposition's threshold
    // drops them (a condition number of the Gram matrix up to 1e12, of ΔF up to 1e6).
    cod_.setThreshold(1e-12);
    cod_.compute(gram);
    gamma_ = cod_.solve(rhs);
    fk.noalias() -= dx_.leftCols(stored_) * gamma_;
    fk.noalias() -= df * gamma_;
  }

 private:
  Eigen::Index depth_;
  Eigen::MatrixXd dx_, df_;  ///< columns: differences of successive iterates and corrections
  Eigen::Index stored_ = 0, next_ = 0;
  Eigen::VectorXd x_prev_, f_prev_, gamma_;
  Eigen::MatrixXd wdf_;
  std::vector<double> buffer_;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_;
  bool have_prev_ = false;
};

}  // namespace hencky
