#include "solve/rigid_motions.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace hencky {
namespace {

/// The spectral parts of a 6×6 positive semidefinite matrix: its null space and the range with
/// its eigenvalues. An eigenvalue up to 1e-10 of the largest (or of 1) counts as zero. One
/// 6×6 symmetric eigensolver does all the linear algebra of this file: it is exact enough for
/// these small, well-scaled matrices, and one template instance keeps the file quick to build.
struct Spectrum {
  Eigen::SelfAdjointEigenSolver<Mat6d> eig;
  std::vector<int> zero, positive;
  explicit Spectrum(const Mat6d& a) : eig(a) {
    const double top = std::max(eig.eigenvalues().maxCoeff(), 1.0);
    for (int i = 0; i < 6; ++i)
      (eig.eigenvalues()[i] > 1e-10 * top ? positive : zero).push_back(i);
  }
  Eigen::MatrixXd columns(const std::vector<int>& which) const {
    Eigen::MatrixXd c(6, which.size());
    for (std::size_t k = 0; k < which.size(); ++k) c.col(k) = eig.eigenvectors().col(which[k]);
    return c;
  }
  /// The Moore–Penrose inverse.
  Mat6d pseudo_inverse() const {
    Mat6d p = Mat6d::Zero();
    for (int i : positive) {
      const Vec6d v = eig.eigenvectors().col(i);
      p += v * v.transpose() / eig.eigenvalues()[i];
    }
    return p;
  }
};

std::string point_text(const Vec3& p, double size) {
  auto c = [&](double v) { return std::abs(v) < 1e-9 * size ? 0.0 : v; };
  return fmt::format("({:.4g}, {:.4g}, {:.4g})", c(p.x()), c(p.y()), c(p.z()));
}

}  // namespace

Eigen::MatrixXd free_motions(const Mat6d& a) {
  const Spectrum s(a);
  return s.columns(s.zero);
}

/// The free motions of null space `n` in words: the translations along x, y, z and the
/// rotations about axes along x, y, z it contains, then any other motion it holds.
std::vector<std::string> describe_motions(const Eigen::MatrixXd& n, const Vec3& centre, double size) {
  static const char* axis[3] = {"x", "y", "z"};
  const Mat6d q = Mat6d::Identity() - n * n.transpose();  // the held part of a motion
  std::vector<std::string> out;
  Eigen::MatrixXd found(6, 0);
  auto keep = [&](const Vec6d& v) {
    found.conservativeResize(6, found.cols() + 1);
    found.col(found.cols() - 1) = v.normalized();
  };
  for (int i = 0; i < 3; ++i) {
    const Vec6d t = Vec6d::Unit(i);
    if ((q * t).norm() < 1e-6) {
      out.push_back(fmt::format("translation along {}", axis[i]));
      keep(t);
    }
  }
  for (int j = 0; j < 3; ++j) {
    // The rotation about some axis along e_j: [t; e_j] with the t that holds it least.
    // t = −(q's translation columns)⁺ q e_j, the least-squares t of least norm.
    Mat6d qt = Mat6d::Zero();
    qt.leftCols<3>() = q.leftCols<3>();
    const Vec6d rot = Vec6d::Unit(3 + j);
    const Vec6d t6 = -Spectrum(qt.transpose() * qt).pseudo_inverse() * qt.transpose() * (q * rot);
    const Vec3 t = t6.head<3>();
    Vec6d v = rot;
    v.head<3>() = t;
    if ((q * v).norm() > 1e-6 * v.norm()) continue;
    const Vec3 e = Vec3::Unit(j);
    const Vec3 across = t - t.dot(e) * e;  // the part of t along e is a translation
    const Vec3 p = centre + size * e.cross(across);
    out.push_back(
        fmt::format("rotation about the axis through {} along {}", point_text(p, size), axis[j]));
    v.head<3>() = across;
    keep(v);
  }
  // What the coordinate motions do not span: described by their vectors.
  if (found.cols() < n.cols()) {
    // The part of n outside the span of what was found, and an orthonormal basis of it (the
    // range of rest restᵀ: the left singular vectors of rest above 1e-5).
    const Spectrum spanned(found * found.transpose());
    const Eigen::MatrixXd in_span = spanned.columns(spanned.positive);
    const Eigen::MatrixXd rest = n - in_span * (in_span.transpose() * n);
    const Spectrum left(rest * rest.transpose());
    for (int k : left.positive) {
      const Vec6d v = left.eig.eigenvectors().col(k);
      const Vec3 w(v[3], v[4], v[5]);
      if (w.norm() < 1e-9) {
        out.push_back("translation along " + point_text(Vec3(v[0], v[1], v[2]).normalized(), 1));
        continue;
      }
      const Vec3 e = w.normalized(), t(v[0], v[1], v[2]);
      const Vec3 across = (t - t.dot(e) * e) / w.norm();
      out.push_back(fmt::format("rotation about the axis through {} along {}",
                                point_text(centre + size * e.cross(across), size),
                                point_text(e, 1)));
    }
  }
  return out;
}

}  // namespace hencky
