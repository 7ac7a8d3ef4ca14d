#pragma once
// Anderson acceleration of a fixed-point iteration (solver.acceleration: anderson).
//
// The fixed-matrix schemes (initial-stress, initial-stress-stiffness) iterate
// u_{k+1} = G(u_k) = u_k + K⁻¹ r(u_k) with one factorization of K: a fixed-point iteration that
// contracts linearly, slowly where the plastic zone's stiffness is far from K's. Anderson's
// method (D. G. Anderson, J. ACM 12, 1965; in the form of H. F. Walker and P. Ni, SIAM J.
// Numer. Anal. 49, 2011) takes the next iterate as the combination of the last m + 1 iterates
// whose corrections f_k = K⁻¹ r(u_k) best cancel:
//   γ = argmin ‖f_k − ΔF γ‖,  u_{k+1} = u_k + f_k − (ΔU + ΔF) γ,
// with ΔU, ΔF the differences of the last m iterates and corrections. It costs m vectors and a
// small least-squares problem per iteration, no factorization, and is a secant (multisecant
// quasi-Newton) method built on the scheme's own iteration: the fixed point, and so the answer,
// is the scheme's.
#include <Eigen/Dense>
#include <algorithm>
#include <vector>

namespace hencky {

class Anderson {
 public:
  explicit Anderson(int depth) : depth_(depth) {}

  /// Forgets the history: the next step is the plain one (after the map G changed: a new
  /// matrix, a new step, or a step that made things worse).
  void reset() {
    stored_ = next_ = 0;
    have_prev_ = false;
  }

  /// `u`: the current iterate (free unknowns); `f`: its plain correction G(u) − u, replaced by
  /// the accelerated one. The history is kept as columns of two n × depth matrices, the oldest
  /// column overwritten when they are full (the least-squares weights do not depend on the
  /// order of the columns): after the first iterations of a problem nothing is allocated.
  void accelerate(const std::vector<double>& u, std::vector<double>& f) {
    const Eigen::Index n = static_cast<Eigen::Index>(u.size());
    const Eigen::Map<const Eigen::VectorXd> uk(u.data(), n);
    Eigen::Map<Eigen::VectorXd> fk(f.data(), n);
    if (du_.rows() != n) {
      du_.resize(n, depth_);
      df_.resize(n, depth_);
      reset();
    }
    if (have_prev_) {
      const Eigen::Index col = next_ % depth_;
      du_.col(col) = uk - u_prev_;
      df_.col(col) = fk - f_prev_;
      next_ = col + 1;
      stored_ = std::min<Eigen::Index>(stored_ + 1, depth_);
    }
    u_prev_ = uk;
    f_prev_ = fk;
    have_prev_ = true;
    if (stored_ == 0) return;
    qr_.compute(df_.leftCols(stored_));
    gamma_ = qr_.solve(f_prev_);
    fk.noalias() -= du_.leftCols(stored_) * gamma_;
    fk.noalias() -= df_.leftCols(stored_) * gamma_;
  }

 private:
  Eigen::Index depth_;
  Eigen::MatrixXd du_, df_;  ///< columns: differences of successive iterates and corrections
  Eigen::Index stored_ = 0, next_ = 0;
  Eigen::VectorXd u_prev_, f_prev_, gamma_;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_;
  bool have_prev_ = false;
};

}  // namespace hencky
