#include "fem/geometry.hpp"

#include <algorithm>
#include <cmath>

namespace hencky {

double physical_gradients(const ReferenceTable& t, int q, std::span<const Vec3> x, double* dNdx) {
  const int n = t.n_nodes;
  const double* dN = &t.dN[static_cast<std::size_t>(q) * n * 3];
  Mat3 J = Mat3::Zero();  // J(i, k) = dx_i / dξ_k
  for (int a = 0; a < n; ++a)
    for (int k = 0; k < 3; ++k) J.col(k) += x[a] * dN[3 * a + k];
  const double det = J.determinant();
  if (!(det > 0)) return det;
  const Mat3 Jinv_t = J.inverse().transpose();  // dN/dx = J^{-T} dN/dξ
  for (int a = 0; a < n; ++a) {
    const Vec3 g = Jinv_t * Vec3(dN[3 * a], dN[3 * a + 1], dN[3 * a + 2]);
    dNdx[3 * a] = g[0];
    dNdx[3 * a + 1] = g[1];
    dNdx[3 * a + 2] = g[2];
  }
  return det;
}

Vec3 point_position(const ReferenceTable& t, int q, std::span<const Vec3> x) {
  Vec3 p = Vec3::Zero();
  const double* N = &t.N[static_cast<std::size_t>(q) * t.n_nodes];
  for (int a = 0; a < t.n_nodes; ++a) p += N[a] * x[a];
  return p;
}

Vec3 face_normal(const ReferenceTable& t, int q, std::span<const Vec3> x) {
  const int n = t.n_nodes;
  const double* dN = &t.dN[static_cast<std::size_t>(q) * n * 2];
  Vec3 t1 = Vec3::Zero(), t2 = Vec3::Zero();
  for (int a = 0; a < n; ++a) {
    t1 += x[a] * dN[2 * a];
    t2 += x[a] * dN[2 * a + 1];
  }
  return t1.cross(t2);
}

double CellKinematics::compute(const ReferenceTable& t, std::span<const Vec3> x) {
  n = t.n_nodes;
  points = t.n_points;
  bbar = uses_bbar(t.type);
  volume = 0;
  double det_min = INFINITY;
  for (int q = 0; q < points; ++q) {
    const double det = physical_gradients(t, q, x, &g[static_cast<std::size_t>(q) * 3 * n]);
    det_min = std::min(det_min, det);
    dv[q] = det * t.weights[q];
    volume += dv[q];
  }
  if (!bbar || !(det_min > 0)) return det_min;
  double mean[3 * max_cell_nodes] = {};
  for (int q = 0; q < points; ++q)
    for (int i = 0; i < 3 * n; ++i) mean[i] += dv[q] * grad(q)[i];
  for (int i = 0; i < 3 * n; ++i) mean[i] /= volume;
  for (int q = 0; q < points; ++q)
    for (int i = 0; i < 3 * n; ++i) d[static_cast<std::size_t>(q) * 3 * n + i] = mean[i] - grad(q)[i];
  return det_min;
}

Voigt CellKinematics::strain(int q, const double* u) const {
  Voigt e = strain_from_gradients(n, grad(q), u);
  if (bbar) {
    const double* c = corr(q);
    double dtheta = 0;
    for (int i = 0; i < 3 * n; ++i) dtheta += c[i] * u[i];
    for (int i = 0; i < 3; ++i) e[i] += dtheta / 3;
  }
  return e;
}

void CellKinematics::add_bt_sigma(int q, const Voigt& s, double w, double* f) const {
  hencky::add_bt_sigma(n, grad(q), s, w, f);
  if (bbar) {
    const double* c = corr(q);
    const double p = w * (s[0] + s[1] + s[2]) / 3;
    for (int i = 0; i < 3 * n; ++i) f[i] += p * c[i];
  }
}

Mat3 CellKinematics::gradient(int q, const double* u) const {
  Mat3 L = Mat3::Zero();
  const double* gq = grad(q);
  for (int a = 0; a < n; ++a)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) L(i, j) += u[3 * a + i] * gq[3 * a + j];
  return L;
}

Mat3 hughes_winget_rotation(const Mat3& L) {
  const Mat3 half_w = 0.25 * (L - L.transpose());
  // I − W/2 is invertible for every skew W (its eigenvalues are 1 and 1 ± i·|w|/2).
  return (Mat3::Identity() - half_w).inverse() * (Mat3::Identity() + half_w);
}

namespace {
/// A symmetric tensor from Voigt {11, 22, 33, 23, 31, 12}, shears divided by `shear`.
Mat3 tensor_of(const Voigt& v, double shear) {
  Mat3 t;
  t << v[0], v[5] / shear, v[4] / shear, v[5] / shear, v[1], v[3] / shear, v[4] / shear,
      v[3] / shear, v[2];
  return t;
}
Voigt voigt_of(const Mat3& t, double shear) {
  Voigt v;
  v << t(0, 0), t(1, 1), t(2, 2), shear * t(1, 2), shear * t(0, 2), shear * t(0, 1);
  return v;
}
}  // namespace

Mat3 stress_tensor(const Voigt& s) {
  return tensor_of(s, 1);
}

Voigt rotate_stress(const Mat3& R, const Voigt& s) {
  return voigt_of(R * tensor_of(s, 1) * R.transpose(), 1);
}

Voigt rotate_strain(const Mat3& R, const Voigt& e) {
  return voigt_of(R * tensor_of(e, 2) * R.transpose(), 2);
}

namespace {
bool inside_reference(CellType type, const double* xi, double tol) {
  switch (type) {
    case CellType::tet4:
    case CellType::tet10:
      return xi[0] >= -tol && xi[1] >= -tol && xi[2] >= -tol && xi[0] + xi[1] + xi[2] <= 1 + tol;
    case CellType::wedge6:
      return xi[0] >= -tol && xi[1] >= -tol && xi[0] + xi[1] <= 1 + tol && std::abs(xi[2]) <= 1 + tol;
    default:
      return std::abs(xi[0]) <= 1 + tol && std::abs(xi[1]) <= 1 + tol && std::abs(xi[2]) <= 1 + tol;
  }
}
}  // namespace

bool locate_in_cell(CellType type, std::span<const Vec3> x, const Vec3& p, double tol, double xi[3]) {
  const int n = cell_n_nodes(type);
  double N[max_cell_nodes], dN[3 * max_cell_nodes];
  // Start at the reference centroid.
  const bool simplex_like = type == CellType::tet4 || type == CellType::tet10;
  xi[0] = xi[1] = simplex_like ? 0.25 : (type == CellType::wedge6 ? 1.0 / 3 : 0.0);
  xi[2] = simplex_like ? 0.25 : 0.0;
  for (int it = 0; it < 30; ++it) {
    shape_values(type, xi, N);
    shape_gradients(type, xi, dN);
    Vec3 r = -p;
    Mat3 J = Mat3::Zero();
    for (int a = 0; a < n; ++a) {
      r += N[a] * x[a];
      for (int k = 0; k < 3; ++k) J.col(k) += x[a] * dN[3 * a + k];
    }
    const double det = J.determinant();
    if (!(std::abs(det) > 0)) return false;
    const Vec3 d = J.inverse() * r;
    for (int k = 0; k < 3; ++k) xi[k] -= d[k];
    if (d.norm() < 1e-13) break;
    if (d.norm() > 1e3) return false;
  }
  return inside_reference(type, xi, tol);
}

}  // namespace hencky
