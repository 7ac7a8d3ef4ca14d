#pragma once
// Isotropic thermo-elasticity at a material point: Hooke's matrix D (1.16), compliance A (1.4)
// and the thermal strain increment of (1.9), as pure functions.
#include "core/types.hpp"

namespace hencky {

/// E, ν, α at one temperature. α is the secant coefficient: thermal strain = α(T)·T − α(T_ref)·T_ref.
struct ElasticConstants {
  double E = 0, nu = 0, alpha = 0;

  double shear_modulus() const { return E / (2 * (1 + nu)); }
  double lame_lambda() const { return E * nu / ((1 + nu) * (1 - 2 * nu)); }

  /// D in Voigt order {11,22,33,23,31,12} with engineering shears, (1.15)-(1.16).
  Mat6 stiffness() const {
    const double l = lame_lambda(), g = shear_modulus();
    Mat6 d = Mat6::Zero();
    d.topLeftCorner<3, 3>().setConstant(l);
    for (int i = 0; i < 3; ++i) {
      d(i, i) = l + 2 * g;
      d(i + 3, i + 3) = g;
    }
    return d;
  }
  /// A = D^{-1}, (1.4) in Voigt form.
  Mat6 compliance() const {
    Mat6 a = Mat6::Zero();
    a.topLeftCorner<3, 3>().setConstant(-nu / E);
    for (int i = 0; i < 3; ++i) {
      a(i, i) = 1 / E;
      a(i + 3, i + 3) = 2 * (1 + nu) / E;
    }
    return a;
  }
  /// Total thermal strain α(T)·T (volumetric part only).
  double thermal_strain(double T) const { return alpha * T; }
};

inline Voigt volumetric(double v) {
  Voigt e;
  e << v, v, v, 0, 0, 0;
  return e;
}

/// Thermal strain increment of (1.9) from state (c0, T0, σ0) at t to (c1, T1) at t+Δt:
/// Δ(αT)·δ plus ΔA·σ(t), the strain that the change of compliance produces under the stress
/// already carried. With it, a step-by-step elastic path ends where a single step does.
inline Voigt thermal_strain_increment(const ElasticConstants& c0, double T0,
                                      const ElasticConstants& c1, double T1, const Voigt& sigma0) {
  return volumetric(c1.thermal_strain(T1) - c0.thermal_strain(T0)) +
         (c1.compliance() - c0.compliance()) * sigma0;
}

/// Elastic point update, (1.12) with (1.14): σ(t+Δt) = σ(t) + D(t+Δt)(Δε − Δε^th).
inline Voigt elastic_stress_update(const ElasticConstants& c0, double T0, const ElasticConstants& c1,
                                   double T1, const Voigt& sigma0, const Voigt& d_eps) {
  return sigma0 + c1.stiffness() * (d_eps - thermal_strain_increment(c0, T0, c1, T1, sigma0));
}

/// von Mises equivalent stress sqrt(σ^T M σ), (1.17).
inline double von_mises(const Voigt& s) {
  const double a = s[0] - s[1], b = s[1] - s[2], c = s[2] - s[0];
  return std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

}  // namespace hencky
