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
Voigt stress_voigt(const Mat3& t) {
  return voigt_of(t, 1);
}
Mat3 strain_tensor(const Voigt& e) {
  return tensor_of(e, 2);
}
Voigt strain_voigt(const Mat3& t) {
  return voigt_of(t, 2);
}

Voigt rotate_strain(const Mat3& R, const Voigt& e) {
  return voigt_of(R * tensor_of(e, 2) * R.transpose(), 2);
}

Voigt rotate_stress(const Mat3& R, const Voigt& s) {
  return voigt_of(R * tensor_of(s, 1) * R.transpose(), 1);
}

double CellDeformation::compute(const CellKinematics& kin, const double* du) {
  n = kin.n;
  points = kin.points;
  bbar = kin.bbar;
  double det_min = INFINITY, mean_trace = 0;
  Vec3 mean_fg[max_cell_nodes];
  for (int a = 0; a < n; ++a) mean_fg[a] = Vec3::Zero();
  for (int q = 0; q < points; ++q) {
    F[q] = Mat3::Identity() + kin.gradient(q, du);
    J[q] = F[q].determinant();
    det_min = std::min(det_min, J[q]);
    F_inv[q] = F[q].inverse();
    const Mat3 e = 0.5 * (F[q].transpose() * F[q] - Mat3::Identity());
    E[q] = voigt_of(e, 2);
    if (!bbar) continue;
    mean_trace += kin.dv[q] * e.trace();
    const double* g = kin.grad(q);
    for (int a = 0; a < n; ++a)
      mean_fg[a] += kin.dv[q] * F[q] * Vec3(g[3 * a], g[3 * a + 1], g[3 * a + 2]);
  }
  if (!bbar || !(det_min > 0)) return det_min;
  mean_trace /= kin.volume;
  for (int a = 0; a < n; ++a) mean_fg[a] /= kin.volume;
  for (int q = 0; q < points; ++q) {
    const double shift = (mean_trace - (E[q][0] + E[q][1] + E[q][2])) / 3;
    for (int i = 0; i < 3; ++i) E[q][i] += shift;
    // C̄ = I + 2Ē must stay positive definite (Hencky's strain is ½ ln C̄): a shift of the trace
    // that compresses a direction of the point to nothing is as inverted as det F ≤ 0 (the
    // first iterate of a step whose prescribed displacements crush a boundary layer).
    const Mat3 cb = Mat3::Identity() + 2 * tensor_of(E[q], 2);
    const double m2 = cb(0, 0) * cb(1, 1) - cb(0, 1) * cb(1, 0);
    if (!(cb(0, 0) > 0 && m2 > 0 && cb.determinant() > 0)) det_min = std::min(det_min, 0.0);
    const double* g = kin.grad(q);
    double* cq = &c[static_cast<std::size_t>(q) * 3 * n];
    for (int a = 0; a < n; ++a) {
      const Vec3 ca = F_inv[q] * mean_fg[a] - Vec3(g[3 * a], g[3 * a + 1], g[3 * a + 2]);
      for (int i = 0; i < 3; ++i) cq[3 * a + i] = ca[i];
    }
  }
  return det_min;
}

void CellDeformation::add_force(const CellKinematics& kin, int q, const Voigt& S, double w,
                                double* f) const {
  const Mat3 s = tensor_of(S, 1), fs = w * F[q] * s;
  const double p = w * (S[0] + S[1] + S[2]) / 3;
  const double* g = kin.grad(q);
  for (int a = 0; a < n; ++a) {
    Vec3 v = fs * Vec3(g[3 * a], g[3 * a + 1], g[3 * a + 2]);
    if (bbar) v += p * (F[q] * Vec3(corr(q)[3 * a], corr(q)[3 * a + 1], corr(q)[3 * a + 2]));
    for (int i = 0; i < 3; ++i) f[3 * a + i] += v[i];
  }
}

Mat3 CellDeformation::rotation(int q) const {
  const Eigen::JacobiSVD<Mat3> svd(F[q], Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
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
