#include "material/kinematic.hpp"

#include <fmt/format.h>

#include <array>

namespace hencky {

KinematicReturn kinematic_return(const ElasticConstants& k, const StepCurve& curve, double h_kin,
                                 const Voigt& sigma0, const Voigt& alpha0, const Voigt& d_eps_ep) {
  KinematicReturn r;
  r.mapping = radial_return(k, curve, sigma0 - alpha0, d_eps_ep, h_kin);
  r.mapping.sigma += alpha0;
  r.alpha = alpha0;
  if (!r.mapping.plastic) return r;
  // dα = (2/3)·H_k·Δε^p with Δε^p = Δλ·Z, Z = Mξ/ξ̃ (engineering shears): as a stress,
  // (2/3)·(3/2)·H_k·Δλ·dev(ξ)/ξ̃ = H_k·Δλ·dev(ξ)/ξ̃, whose normal part is (2/3)·H_k·Δλ·Z and
  // whose shear part is (1/3)·H_k·Δλ·Z.
  const Voigt& z = r.mapping.z;
  const double a = h_kin * r.mapping.d_lambda;
  Voigt d_alpha;
  d_alpha << 2 * a * z[0] / 3, 2 * a * z[1] / 3, 2 * a * z[2] / 3, a * z[3] / 3, a * z[4] / 3,
      a * z[5] / 3;
  r.alpha += d_alpha;
  return r;
}

namespace {

/// The deviator of a stress-like vector.
Voigt deviator(const Voigt& s) {
  const double p = (s[0] + s[1] + s[2]) / 3;
  Voigt d = s;
  d[0] -= p;
  d[1] -= p;
  d[2] -= p;
  return d;
}

}  // namespace

ReturnMapping armstrong_frederick_return(const ElasticConstants& k, const StepCurve& curve,
                                         std::span<const BackStressLaw> laws, const Voigt& sigma0,
                                         std::span<const Voigt> alpha0, const Voigt& d_eps_ep,
                                         std::span<Voigt> alpha) {
  ReturnMapping r;
  const Voigt sigma_tr = sigma0 + k.stiffness() * d_eps_ep;
  const Voigt s_tr = deviator(sigma_tr);
  const std::size_t m = laws.size();
  Voigt a_sum = Voigt::Zero();
  for (std::size_t i = 0; i < m; ++i) {
    alpha[i] = alpha0[i];
    a_sum += alpha0[i];
  }
  const double g2 = 2 * k.shear_modulus(), three_g = curve.three_g;
  const double q_tr = von_mises(Voigt(s_tr - a_sum));
  r.sigma = sigma_tr;
  r.z = flow_direction(Voigt(s_tr - a_sum));
  const double h0 = curve.yield_now, scale = std::max(q_tr, h0);
  if (q_tr - h0 <= 1e-12 * scale || q_tr == 0) return r;  // elastic
  // ξ*(Δλ) and f(Δλ) = q(ξ*) − (3G + Σ C_iβ_i)Δλ − H(ε̃^p + Δλ), β_i = 1/(1 + γ_iΔλ), and
  // f' = N:a' − (3G + Σ C_iβ_i² + H'), N = (3/2)ξ*/q*, a' = Σ γ_iβ_i²α_i(t): f decreases
  // (N:a' ≤ Σ β_i²C_i where |α_i| stays within C_i/γ_i), from f(0) > 0 to below 0 at
  // q(s_tr) + Σ q(α_i)... over 3G.
  double q_bound = von_mises(s_tr);
  for (std::size_t i = 0; i < m; ++i) q_bound += von_mises(alpha0[i]);
  Voigt xi, a_prime;
  double q = 0, h = 0;
  auto f = [&](double dl) {
    xi = s_tr;
    a_prime.setZero();
    double c_beta = 0, c_beta2 = 0;
    for (std::size_t i = 0; i < m; ++i) {
      const double beta = 1 / (1 + laws[i].gamma * dl);
      xi -= beta * alpha0[i];
      a_prime += laws[i].gamma * beta * beta * alpha0[i];
      c_beta += laws[i].c * beta;
      c_beta2 += laws[i].c * beta * beta;
    }
    q = von_mises(xi);
    const auto iso = curve.hardening->plastic(curve.eps_p + dl, curve.temperature);
    // N:a' with N = (3/2)ξ/q: Mξ·a'/q, a' being deviatoric (plastic_point.hpp's m_times).
    const double n_a = q > 0 ? m_times(xi).dot(a_prime) / q : 0.0;
    h = three_g + c_beta2 + iso.slope - n_a;
    return q - (three_g + c_beta) * dl - iso.value;
  };
  double lo = 0, hi = q_bound / three_g, dl = 0, val = f(0);
  for (int it = 0; it < 200; ++it) {
    if (std::abs(val) <= 1e-14 * scale || hi - lo <= 1e-16 * std::max(1.0, hi)) break;
    if (val > 0)
      lo = dl;
    else
      hi = dl;
    double next = dl + val / h;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    dl = next;
    val = f(dl);
  }
  r.d_lambda = dl;
  r.plastic = dl > 0;
  if (!r.plastic) return r;
  // N = (3/2)ξ*/q*: Δε^p = Δλ·N (tensor), σ = σ_tr − 2GΔλN, α_i = β_i(α_i(t) + (2/3)C_iΔλN).
  const Voigt n_dir = 1.5 * xi / q;
  r.sigma = sigma_tr - g2 * dl * n_dir;
  r.z = m_times(xi) / q;  // engineering shears: the plastic strain increment is z·Δλ
  for (std::size_t i = 0; i < m; ++i)
    alpha[i] = (alpha0[i] + (2.0 / 3.0) * laws[i].c * dl * n_dir) / (1 + laws[i].gamma * dl);
  // The tangent (the header): C = D − θ'·2G·I_dev + 2G(θ' − 3G/h)·n nᵀ, n the unit deviator
  // along ξ*, θ' = 3GΔλ/q*.
  const double ratio = three_g * dl / q;
  r.tangent.dev_scale = -ratio;
  r.tangent.coef = g2 * (ratio - three_g / h);
  r.tangent.v = xi / (std::sqrt(2.0 / 3.0) * q);  // |ξ| = sqrt(2/3)·q
  return r;
}

KinematicLaw::KinematicLaw(std::vector<PropertyTable> c, std::vector<PropertyTable> gamma)
    : c_(std::move(c)), gamma_(std::move(gamma)) {
  for (const PropertyTable& g : gamma_)
    for (double v : g.value) linear_ = linear_ && v == 0;
  variables_.push_back(LawVariable{"back_stress", 6});
  if (!linear_)
    for (std::size_t i = 2; i <= c_.size(); ++i)
      variables_.push_back(LawVariable{fmt::format("back_stress_{}", i), 6});
}

std::span<const LawVariable> KinematicLaw::variables() const {
  return variables_;
}

double KinematicLaw::modulus(double T) const {
  double h = 0;
  for (const PropertyTable& c : c_) h += c(T);
  return h;
}

ReturnMapping KinematicLaw::update(const ElasticConstants& k, const StepCurve& curve,
                                   const Voigt& sigma0, const Voigt& d_mech,
                                   std::span<const double> state0, std::span<double> state1) const {
  const Voigt alpha0 = Eigen::Map<const Voigt>(state0.data());
  if (linear_) {  // Prager: one back stress of modulus ΣC_i, the return of radial_return
    const KinematicReturn r =
        kinematic_return(k, curve, modulus(curve.temperature), sigma0, alpha0, d_mech);
    Eigen::Map<Voigt>(state1.data()) = r.alpha;
    return r.mapping;
  }
  // The state: α = Σα_i, then α_2 .. α_m; α_1 = α − (α_2 + .. + α_m).
  // On the stack: this runs at every point in every iteration (max_back_stresses bounds m).
  const std::size_t m = c_.size();
  std::array<BackStressLaw, max_back_stresses> laws;
  std::array<Voigt, max_back_stresses> a0, a1;
  a0[0] = alpha0;
  for (std::size_t i = 0; i < m; ++i) {
    laws[i] = {c_[i](curve.temperature), gamma_[i](curve.temperature)};
    if (i > 0) {
      a0[i] = Eigen::Map<const Voigt>(state0.data() + 6 * i);
      a0[0] -= a0[i];
    }
  }
  const ReturnMapping r = armstrong_frederick_return(
      k, curve, std::span<const BackStressLaw>(laws.data(), m), sigma0,
      std::span<const Voigt>(a0.data(), m), d_mech, std::span<Voigt>(a1.data(), m));
  Voigt total = Voigt::Zero();
  for (std::size_t i = 0; i < m; ++i) {
    total += a1[i];
    if (i > 0) Eigen::Map<Voigt>(state1.data() + 6 * i) = a1[i];
  }
  Eigen::Map<Voigt>(state1.data()) = total;
  return r;
}

LawDeclaration kinematic_law_declaration() {
  LawDeclaration d;
  d.name = "kinematic";
  d.keys = {
      LawKey{"kinematic", {"C", "gamma"}, "C in Pa (dα/dε^p, the back stress's modulus), gamma 1"}};
  d.make = [](const PlasticitySpec& spec) -> std::shared_ptr<const PointLaw> {
    const auto& groups = spec.law.keys.at("kinematic");
    std::vector<PropertyTable> c, gammas;
    if (groups.size() > max_back_stresses)
      throw InputError(spec.law.where, fmt::format("{} back stresses: hencky takes at most {}",
                                                   groups.size(), max_back_stresses));
    for (const auto& g : groups) {
      const PropertyTable& gamma = g.at("gamma");
      for (double v : gamma.value)
        if (!(v >= 0))
          throw InputError(
              gamma.where,
              fmt::format("gamma = {:g}: expected a rate >= 0 (0: linear, Prager)", v));
      gammas.push_back(gamma);
      const PropertyTable& ci = g.at("C");
      for (double v : ci.value)
        if (!(v >= 0))
          throw InputError(ci.where, fmt::format("C = {:g}: expected a modulus >= 0 (Pa)", v));
      c.push_back(ci);
    }
    if (spec.unloading != PlasticitySpec::Unloading::elastic)
      throw InputError(spec.law.where,
                       "kinematic hardening needs elastic unloading (unloading: elastic, the "
                       "default): a moving yield surface has no deformation-theory form");
    return std::make_shared<KinematicLaw>(std::move(c), std::move(gammas));
  };
  return d;
}

}  // namespace hencky
