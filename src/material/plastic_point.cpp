#include "material/plastic_point.hpp"

#include <algorithm>

namespace hencky {

Mat6 Tangent::matrix(const ElasticConstants& k) const {
  const double l = lambda(k), m = mu(k);
  Mat6 c = Mat6::Zero();
  c.topLeftCorner<3, 3>().setConstant(l);
  for (int i = 0; i < 3; ++i) {
    c(i, i) = l + 2 * m;
    c(i + 3, i + 3) = m;
  }
  return c + coef * v * v.transpose();
}

Voigt Tangent::times(const ElasticConstants& k, const Voigt& e) const {
  const double l = lambda(k), m = mu(k), tr = e[0] + e[1] + e[2];
  Voigt s;
  s << l * tr + 2 * m * e[0], l * tr + 2 * m * e[1], l * tr + 2 * m * e[2], m * e[3], m * e[4],
      m * e[5];
  return s + coef * v.dot(e) * v;
}

Tangent d_tilde(const ElasticConstants& k, const Voigt& z, double tan_beta, double theta) {
  const double three_g = 3 * k.shear_modulus();
  if (tan_beta == three_g && theta == 1) return Tangent{};  // β* = β^e: D̃ = D, (2.13)
  Tangent t;
  t.v = k.stiffness() * z;  // DZ
  const double zdz = z.dot(t.v);
  if (zdz <= 0) return Tangent{};  // Z = 0: no direction yet, D̃ = D
  if (theta == 1) {
    // −1/(E* + ZᵀDZ) with E* = tanβ·3G/(3G − tanβ), (2.11), multiplied through by (3G − tanβ).
    t.coef = -(three_g - tan_beta) / (tan_beta * three_g + zdz * (three_g - tan_beta));
    return t;
  }
  // Across Z the deviator scaled by θ; along Z, Zᵀ C x = (1 + dev_scale + coef·ZᵀDZ)·ZᵀDx, which
  // is to be tan β*/3G · ZᵀDx.
  t.dev_scale = theta - 1;
  t.coef = (tan_beta / three_g - theta) / zdz;
  return t;
}

Mat6 y_tilde(const ElasticConstants& k, const Voigt& z, double tan_beta) {
  const Tangent t = d_tilde(k, z, tan_beta);
  return -t.coef * z * t.v.transpose();  // Z (ZᵀD) / (E* + ZᵀDZ)
}

StepCurve::StepCurve(const Hardening& h, double T, double three_g_, double eps_p_, bool elastic)
    : hardening(&h), temperature(T), three_g(three_g_), eps_p(eps_p_), elastic_unloading(elastic) {
  yield_now = h.plastic(eps_p, T).value;
  eps_yield_now = eps_p + yield_now / three_g;
}

Hardening::Point StepCurve::phi(double eps, bool right) const {
  if (elastic_unloading && (eps < eps_yield_now || (eps == eps_yield_now && !right)))
    return {three_g * (eps - eps_p), three_g};
  return hardening->phi(eps, temperature, three_g);
}

Hardening::Point StepCurve::f(double sigma, bool right) const {
  if (elastic_unloading && (sigma < yield_now || (sigma == yield_now && !right)))
    return {eps_p + sigma / three_g, 1 / three_g};
  return hardening->f(sigma, temperature, three_g);
}

ReturnMapping radial_return(const ElasticConstants& k, const StepCurve& curve,
                            const Voigt& sigma0, const Voigt& d_eps_ep, double h_kin) {
  ReturnMapping r;
  const Mat6 d = k.stiffness();
  const Voigt sigma_tr = sigma0 + d * d_eps_ep;
  const double q_tr = von_mises(sigma_tr);
  r.z = flow_direction(sigma_tr);
  r.sigma = sigma_tr;
  const double g2 = 2 * k.shear_modulus(), three_g = curve.three_g;
  const double h0 = curve.yield_now;
  const double scale = std::max(q_tr, h0);
  const double f_tr = q_tr - h0;
  // Elastic: inside the yield surface, or (deformation theory) inside it with no plastic strain
  // to give back. A trial stress that only reaches the surface to round-off is elastic too.
  if (f_tr <= 1e-12 * scale && (curve.elastic_unloading || curve.eps_p == 0)) return r;
  if (q_tr == 0) return r;

  // g(Δλ) = q_tr − 3GΔλ − H(ε̃^p + Δλ) − H_kΔλ decreases (the curve's slope is > −3G); its
  // root lies in [0, q_tr/(3G + H_k)] when loading, in [−ε̃^p, 0] when the curve is followed
  // back. (With H_k = 0 the added terms are exact zeros: the isotropic return to the last bit.)
  double lo = f_tr > 0 ? 0.0 : -curve.eps_p, hi = f_tr > 0 ? q_tr / (three_g + h_kin) : 0.0;
  auto g = [&](double dl, double* slope) {
    const auto h = curve.hardening->plastic(std::max(curve.eps_p + dl, 0.0), curve.temperature);
    *slope = h.slope + h_kin;
    return q_tr - three_g * dl - h.value - h_kin * dl;
  };
  double slope = 0;
  if (f_tr < 0 && g(lo, &slope) <= 0) {
    // All plastic strain is given back and the stress is still below the curve: elastic line.
    r.d_lambda = lo;
  } else {
    double dl = f_tr > 0 ? 0.0 : lo;
    double val = g(dl, &slope);
    for (int it = 0; it < 200; ++it) {
      if (std::abs(val) <= 1e-14 * scale || hi - lo <= 1e-16 * std::max(1.0, hi)) break;
      if (val > 0) lo = dl; else hi = dl;
      double next = dl + val / (three_g + slope);  // Newton on g: g' = −(3G + H')
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      dl = next;
      val = g(dl, &slope);
    }
    r.d_lambda = dl;
  }
  r.plastic = r.d_lambda != 0;
  if (!r.plastic) return r;
  const double h_slope = curve.hardening->plastic(std::max(curve.eps_p + r.d_lambda, 0.0),
                                                  curve.temperature).slope +
                         h_kin;
  r.sigma = sigma_tr - r.d_lambda * (d * r.z);  // D(z·Δλ) = 3GΔλ·s_tr/q_tr
  // Consistent tangent of the radial return (de Souza Neto, Perić & Owen, Computational Methods
  // for Plasticity, 2008, eq. 7.120): C = D − 3GΔλ/q_tr·2G·I_dev
  //   + 2G(3GΔλ/q_tr − 3G/(3G + H'))·N Nᵀ, N the unit deviator of the trial stress.
  const double ratio = three_g * r.d_lambda / q_tr;
  const double p = (sigma_tr[0] + sigma_tr[1] + sigma_tr[2]) / 3;
  Voigt n;
  n << sigma_tr[0] - p, sigma_tr[1] - p, sigma_tr[2] - p, sigma_tr[3], sigma_tr[4], sigma_tr[5];
  n /= std::sqrt(2.0 / 3.0) * q_tr;  // |s| = sqrt(2/3)·σ̃
  r.tangent.dev_scale = -ratio;
  r.tangent.coef = g2 * (ratio - (std::isfinite(h_slope) ? three_g / (three_g + h_slope) : 0.0));
  r.tangent.v = n;
  return r;
}

}  // namespace hencky
