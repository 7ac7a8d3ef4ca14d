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
#include <deque>
#include <vector>

namespace hencky {

class Anderson {
 public:
  explicit Anderson(int depth) : depth_(depth) {}

  /// Forgets the history: the next step is the plain one (after the map G changed: a new
  /// matrix, a new step, or a step that made things worse).
  void reset() {
    du_.clear();
    df_.clear();
    have_prev_ = false;
  }

  /// `u`: the current iterate (free unknowns); `f`: its plain correction G(u) − u, replaced by
  /// the accelerated one.
  void accelerate(const std::vector<double>& u, std::vector<double>& f) {
    const Eigen::Index n = static_cast<Eigen::Index>(u.size());
    const Eigen::Map<const Eigen::VectorXd> uk(u.data(), n);
    Eigen::Map<Eigen::VectorXd> fk(f.data(), n);
    if (have_prev_) {
      du_.push_back(uk - u_prev_);
      df_.push_back(fk - f_prev_);
      if (static_cast<int>(df_.size()) > depth_) {
        du_.pop_front();
        df_.pop_front();
      }
    }
    u_prev_ = uk;
    f_prev_ = fk;
    have_prev_ = true;
    if (df_.empty()) return;
    const Eigen::Index m = static_cast<Eigen::Index>(df_.size());
    Eigen::MatrixXd dF(n, m);
    for (Eigen::Index j = 0; j < m; ++j) dF.col(j) = df_[static_cast<std::size_t>(j)];
    const Eigen::VectorXd gamma = dF.colPivHouseholderQr().solve(f_prev_);
    for (Eigen::Index j = 0; j < m; ++j)
      fk -= gamma[j] * (du_[static_cast<std::size_t>(j)] + df_[static_cast<std::size_t>(j)]);
  }

 private:
  int depth_;
  std::deque<Eigen::VectorXd> du_, df_;
  Eigen::VectorXd u_prev_, f_prev_;
  bool have_prev_ = false;
};

}  // namespace hencky
