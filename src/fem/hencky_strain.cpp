#include "fem/hencky_strain.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "fem/geometry.hpp"

namespace hencky {

Spectral spectral(const Mat3& a) {
  Spectral s;
  // A diagonal tensor (the common case of no step and of a stress-free start) is its own
  // decomposition, exactly.
  if (a(0, 1) == 0 && a(0, 2) == 0 && a(1, 2) == 0) {
    s.values = a.diagonal();
    return s;
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> es(a);
  s.values = es.eigenvalues();
  s.vectors = es.eigenvectors();
  return s;
}

namespace {
template <class G>
Mat3 apply(const Spectral& s, G g) {
  return s.vectors * Vec3(g(s.values[0]), g(s.values[1]), g(s.values[2])).asDiagonal() *
         s.vectors.transpose();
}
}  // namespace

double half_log_difference(double a, double b) {
  if (a == b) return 0.5 / a;
  // ln(a/b) = log1p(x) with x = (a − b)/b: accurate when a and b are close.
  const double d = a - b;
  return 0.5 * std::log1p(d / b) / d;
}

void HenckyStep::start(const Voigt& eps_t) {
  eps_t_ = eps_t;
  b_identity_ = eps_t.isZero(0);
  b_t_ = b_identity_ ? Mat3::Identity()
                     : apply(spectral(strain_tensor(eps_t)), [](double e) { return std::exp(2 * e); });
}

Voigt HenckyStep::increment(const Voigt& E) {
  c_ = spectral(Mat3::Identity() + 2 * strain_tensor(E));
  u_ = c_.values.cwiseSqrt();
  U_ = apply(c_, [](double c) { return std::sqrt(c); });
  U_inv_ = apply(c_, [](double c) { return 1 / std::sqrt(c); });
  // U bᵉ U; with bᵉ = I it is C itself, whose decomposition is known.
  b_ = b_identity_ ? c_ : spectral(U_ * b_t_ * U_);
  const Mat3 eps = apply(b_, [](double b) { return 0.5 * std::log(b); });
  return strain_voigt(eps) - eps_t_;
}

Voigt HenckyStep::second_piola(const Voigt& tau, double j_t) const {
  return stress_voigt(U_inv_ * stress_tensor(tau) * U_inv_ / j_t);
}

Mat3 HenckyStep::d_log_strain(const Mat3& dC, Mat3* dU) const {
  // U² = C: in C's eigenbasis δU_ij = δC_ij / (u_i + u_j).
  Mat3 d = c_.vectors.transpose() * dC * c_.vectors;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) d(i, j) /= u_(i) + u_(j);
  *dU = c_.vectors * d * c_.vectors.transpose();
  const Mat3 db = *dU * b_t_ * U_ + U_ * b_t_ * *dU;
  // The derivative of ½ ln at b in b's eigenbasis (Daleckii and Krein): the divided
  // differences of ½ ln, 1/(2β) on the diagonal.
  Mat3 e = b_.vectors.transpose() * db * b_.vectors;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) e(i, j) *= half_log_difference(b_.values[i], b_.values[j]);
  return b_.vectors * e * b_.vectors.transpose();
}

Mat6 HenckyStep::tangent(const Voigt& S, const Mat6& c_law, double j_t) const {
  const Mat3 s = stress_tensor(S);
  Mat6 t;
  for (int k = 0; k < 6; ++k) {
    Voigt unit = Voigt::Zero();
    unit[k] = 1;
    Mat3 dU;
    const Mat3 de = d_log_strain(2 * strain_tensor(unit), &dU);
    const Mat3 dtau = stress_tensor(c_law * strain_voigt(de));
    const Mat3 ds = U_inv_ * dtau * U_inv_ / j_t - U_inv_ * dU * s - s * dU * U_inv_;
    t.col(k) = stress_voigt(ds);
  }
  return 0.5 * (t + t.transpose());
}

}  // namespace hencky
