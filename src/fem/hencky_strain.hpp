#pragma once
// Hencky's logarithmic strain for one step of the updated Lagrangian formulation
// (solver.geometry: updated), at one integration point.
//
// The material is the multiplicative one, F = Fᵉ Fᵖ, with the elastic logarithmic strain
// εᵉ = ½ ln bᵉ (bᵉ = Fᵉ Fᵉᵀ) and the Kirchhoff stress τ = D εᵉ; the plastic flow is integrated
// by the exponential map (Simo, "Algorithms for static and dynamic multiplicative plasticity
// that preserve the classical return mapping schemes of the infinitesimal theory", CMAME 99,
// 1992; Eterovic and Bathe, IJNME 30, 1990; Weber and Anand, CMAME 79, 1990). Over a step with
// the deformation gradient f relative to the configuration x at its start, the elastic trial
// is bᵉ_tr = f bᵉ(t) fᵀ, and the return to the yield surface is the small-strain one on
// εᵉ_tr = ½ ln bᵉ_tr: for isotropic elasticity the trial Kirchhoff stress is D εᵉ_tr, and the
// point laws and the report's schemes take Δε = εᵉ_tr − εᵉ(t) and τ(t) for the start exactly as
// they take the small strain increment and σ(t) (Miehe, Apel and Lambrecht, CMAME 191, 2002,
// call this the modular structure of logarithmic-strain plasticity). A thermal strain θ·I
// commutes with everything here and enters Δε^th only.
//
// The step is computed in the frame of x: with f = R U, f bᵉ fᵀ = R (U bᵉ U) Rᵀ, so the law
// works on ε̂ = ½ ln(U bᵉ(t) U) and returns τ̂ = Rᵀ τ R; the second Piola–Kirchhoff stress
// relative to x is S = U⁻¹ τ̂ U⁻¹ / J(t), J(t) = dv/dV at t, a function of C = fᵀf = I + 2E
// alone. That is what CellDeformation (fem/geometry.hpp) takes: its internal forces
// ∫ F S ∇N dx are ∫ σ ∇N dv with σ = τ/J, and its B-bar cells give the law C̄ = I + 2Ē.
// A rigid rotation (U = I) leaves τ̂ = τ(t): the stress turns with the body and no strain is
// made, for any size of the step.
#include "core/types.hpp"

namespace hencky {

/// A symmetric tensor's eigenvalues and orthonormal eigenvectors (as columns).
struct Spectral {
  Vec3 values = Vec3::Ones();
  Mat3 vectors = Mat3::Identity();
};
Spectral spectral(const Mat3& a);

/// ½ (ln a − ln b)/(a − b), the divided difference of ½ ln, and its limit 1/(2a) at a = b.
double half_log_difference(double a, double b);

class HenckyStep {
 public:
  /// The point's elastic (and thermal) logarithmic strain at the step's start in the frame of
  /// x, εᵉ(t) = A(t) τ(t) (engineering shears; a thermal part θ·I would cancel in increment()).
  void start(const Voigt& eps_t);
  /// The step's trial for its (B-bar) Green strain E relative to x: U = √(I + 2E) and
  /// ε̂ = ½ ln(U bᵉ(t) U), bᵉ(t) = exp 2εᵉ(t). Returns ε̂ − εᵉ(t), the increment the point law
  /// takes (engineering shears).
  Voigt increment(const Voigt& E);
  /// S = U⁻¹ τ̂ U⁻¹ / J(t) of the Kirchhoff stress τ̂ the law returned (tensor shears).
  Voigt second_piola(const Voigt& tau, double j_t) const;
  /// dS/dE at the last increment(): column k is the change of S (tensor shears) for a unit
  /// change of the k-th engineering component of E, with c_law = dτ̂/dε̂ the law's matrix and
  /// S that of second_piola. Symmetric for a law with a symmetric matrix (made so to round-off).
  Mat6 tangent(const Voigt& S, const Mat6& c_law, double j_t) const;

 private:
  /// δε̂ for a change δC of C.
  Mat3 d_log_strain(const Mat3& dC, Mat3* dU) const;

  Voigt eps_t_ = Voigt::Zero();
  Mat3 b_t_ = Mat3::Identity();
  bool b_identity_ = true;
  Spectral c_;        ///< C = I + 2E
  Vec3 u_ = Vec3::Ones();  ///< the principal stretches √c
  Mat3 U_ = Mat3::Identity(), U_inv_ = Mat3::Identity();
  Spectral b_;        ///< U bᵉ(t) U
};

}  // namespace hencky
