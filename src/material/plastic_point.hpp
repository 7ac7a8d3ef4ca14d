#pragma once
// Von Mises plasticity at one integration point (report 1.17-1.22, 2.9-2.18): the flow
// direction Z, the matrix D̃(β*) and E*, the curve a point follows during one step (with the
// report's elastic unloading), and the radial return with its consistent tangent for the
// reference `newton` scheme. Pure functions: they read the committed state and return new
// values, they never write the state (as Ferrite.jl's plasticity tutorial and deal.II step-42
// keep the constitutive law pure).
#include <cmath>
#include <limits>

#include "material/elastic.hpp"
#include "material/hardening.hpp"

namespace hencky {

inline constexpr double infinity = std::numeric_limits<double>::infinity();

/// M·σ of (1.19)/(1.22): 3/2 times the deviator, shear entries doubled (a strain-like vector
/// with engineering shears, so that Mσ·Δσ is the contraction and σᵀMσ = σ̃²).
inline Voigt m_times(const Voigt& s) {
  const double p = (s[0] + s[1] + s[2]) / 3;
  Voigt r;
  r << 1.5 * (s[0] - p), 1.5 * (s[1] - p), 1.5 * (s[2] - p), 3 * s[3], 3 * s[4], 3 * s[5];
  return r;
}

/// Z = Mσ/σ̃, (2.10): the direction of plastic flow (1.20), with unit strain intensity
/// (ε̃ of Z·λ is |λ|). Zero for a zero stress.
inline Voigt flow_direction(const Voigt& sigma) {
  const double q = von_mises(sigma);
  return q > 0 ? Voigt(m_times(sigma) / q) : Voigt(Voigt::Zero());
}

/// E* of (2.11) for tan β* and tan β^e = 3G; +inf for β* = β^e, 0 for tan β* = 0.
inline double e_star(double tan_beta, double tan_beta_e) {
  if (tan_beta == tan_beta_e) return infinity;
  return tan_beta * tan_beta_e / (tan_beta_e - tan_beta);
}

/// A material tangent kept compactly per integration point:
///   C = D + dev_scale · 2G·I_dev + coef · v vᵀ
/// (I_dev the deviatoric projector in Voigt form with engineering shears). It covers D (both
/// zero), D̃(β*) of (2.9) (v = DZ) and the consistent tangent of the radial return (v = the
/// unit normal). 8 numbers instead of 36 per point.
struct Tangent {
  double dev_scale = 0;
  double coef = 0;
  Voigt v = Voigt::Zero();

  /// The same matrix to the bit (a point's matrix changed, and the system is assembled again).
  bool operator==(const Tangent& o) const {
    return dev_scale == o.dev_scale && coef == o.coef && v == o.v;
  }
  /// The full matrix, for tests and small problems.
  Mat6 matrix(const ElasticConstants& k) const;
  /// Lamé constants of the isotropic part D + dev_scale·2G·I_dev.
  double lambda(const ElasticConstants& k) const {
    return k.lame_lambda() - dev_scale * 2 * k.shear_modulus() / 3;
  }
  double mu(const ElasticConstants& k) const { return k.shear_modulus() * (1 + dev_scale); }
  Voigt times(const ElasticConstants& k, const Voigt& e) const;
};

/// D̃(β*) = D(I − Ỹ), Ỹ = Z(ZᵀD)/(E* + ZᵀDZ), (2.9)-(2.10), as a Tangent. Written with
/// 1/(E* + ZᵀDZ) = (3G − tan β*)/(tan β*·3G + ZᵀDZ·(3G − tan β*)), which has no singularity
/// at β* = β^e (D̃ = D, (2.13)) and gives E* = 0 at tan β* = 0 (perfect plasticity).
/// With θ < 1 the deviatoric part across Z is scaled by θ while Zᵀ·D̃x keeps tan β*·ZᵀDx/3G:
/// the radial return's stiffness across its direction, θ = σ̃/σ̃_tr (variable-stiffness).
Tangent d_tilde(const ElasticConstants& k, const Voigt& z, double tan_beta, double theta = 1);

/// Ỹ of (2.10) as a full matrix (for the identities (2.14)-(2.16) in tests).
Mat6 y_tilde(const ElasticConstants& k, const Voigt& z, double tan_beta);

/// The curve σ̃ = Φ(ε̃^{e+p}) a point follows during one step, at the temperature of t+Δt.
/// With elastic unloading (the report's end of section 2), the part of the curve below the
/// largest intensity reached is replaced by the line of slope 3G through it: with ε̃^p the
/// equivalent plastic strain at t, that line is σ̃ = 3G(ε̃ − ε̃^p) up to the current yield
/// stress H(ε̃^p). With unloading along the curve (deformation theory) Φ is the virgin curve.
struct StepCurve {
  const Hardening* hardening = nullptr;
  double temperature = 0;
  double three_g = 0;          ///< 3G at t+Δt: tan β^e, (2.12)
  double eps_p = 0;            ///< ε̃^p at t
  bool elastic_unloading = true;
  double yield_now = 0;        ///< H(ε̃^p, T): the stress where the elastic line meets the curve
  double eps_yield_now = 0;    ///< ε̃^p + H/3G: the intensity there (the largest reached)

  StepCurve() = default;
  StepCurve(const Hardening& h, double T, double three_g_, double eps_p_, bool elastic);

  /// Φ and dΦ/dε̃. `right`: at the kink ε̃ = eps_yield_now take the slope of the curve
  /// (loading) rather than 3G.
  Hardening::Point phi(double eps, bool right = false) const;
  /// F = Φ⁻¹ and dF/dσ̃ (+inf above the largest stress of the curve).
  Hardening::Point f(double sigma, bool right = false) const;
};

/// Result of the radial return (the `newton` scheme's point update).
struct ReturnMapping {
  Voigt sigma;          ///< stress at t+Δt
  double d_lambda = 0;  ///< Δε̃^p; the plastic strain increment is z·d_lambda
  Voigt z;              ///< flow direction Mσ/σ̃ of the trial stress
  Tangent tangent;      ///< consistent (algorithmic) tangent dσ/dΔε
  bool plastic = false;
};

/// Radial return: σ_tr = σ(t) + D(Δε^{e+p}); when σ̃_tr exceeds H(ε̃^p) the stress returns
/// along the trial deviator to the curve, q_tr − 3GΔλ = H(ε̃^p + Δλ), solved by a safeguarded
/// Newton iteration. With unloading along the curve Δλ may be negative (down to −ε̃^p).
/// `d_eps_ep` is the mechanical strain increment Δε − Δε^th (with the ΔA·σ term of (1.9)).
/// `h_kin`: a linear kinematic hardening modulus H_k (Prager; material/kinematic.hpp), for a
/// return of the stress relative to the back stress (`sigma0` then σ(t) − α(t)): the equation
/// is q_tr − (3G + H_k)Δλ = H(ε̃^p + Δλ), the tangent's H' becomes H' + H_k, and `sigma` is
/// ξ_tr − 3GΔλ·n, the relative trial stress less the plastic correction (add α(t) for σ).
ReturnMapping radial_return(const ElasticConstants& k, const StepCurve& curve,
                            const Voigt& sigma0, const Voigt& d_eps_ep, double h_kin = 0);

}  // namespace hencky
