#pragma once
// Linear kinematic hardening (Prager) combined with the isotropic curve: the yield surface
// σ̃(σ − α) = H(ε̃^p, T) moves with the back stress α, dα = (2/3)·H_k·dε^p (a deviatoric
// stress), so that a uniaxial bar that yielded in tension to a plastic strain ε_p yields again in
// compression at σ = H_k·ε_p − σ_y (the Bauschinger effect) with its elastic range 2σ_y kept
// (for a perfectly plastic isotropic part). The return is the radial return of the stress
// relative to α (radial_return with H_k), after Simo and Hughes, Computational Inelasticity,
// 1998, section 3.3 (J2 with combined linear hardening). A pure function, as radial_return.
// Armstrong–Frederick back stresses (γ > 0, dα = (2/3)·C·dε^p − γ·α·dε̃^p, Chaboche's sum of
// several) saturate at C/γ: armstrong_frederick_return below.
#include <span>
#include <vector>

#include "material/plastic_point.hpp"
#include "material/point_law.hpp"

namespace hencky {

/// The update of a point with back stress `alpha0` at t (deviatoric, stress components).
struct KinematicReturn {
  ReturnMapping mapping;  ///< mapping.sigma is σ(t+Δt); z, d_lambda and the tangent as usual
  Voigt alpha;            ///< α(t+Δt)
};

/// `h_kin`: H_k ≥ 0 (Pa); `curve`: the isotropic part at the step's temperature.
KinematicReturn kinematic_return(const ElasticConstants& k, const StepCurve& curve, double h_kin,
                                 const Voigt& sigma0, const Voigt& alpha0, const Voigt& d_eps_ep);

/// The most back stresses a material may have (a point's update keeps them on the stack).
inline constexpr std::size_t max_back_stresses = 8;

/// One Armstrong–Frederick back stress at the step's temperature: dα = (2/3)·C·dε^p − γ·α·dε̃^p.
struct BackStressLaw {
  double c = 0;      ///< C (Pa)
  double gamma = 0;  ///< γ (1); 0: linear (Prager)
};

/// The update of a point with the back stresses `alpha0` (α_i at t, deviatoric) of the laws
/// `laws`: backward Euler, α_i = (α_i(t) + (2/3)·C_i·Δε^p)/(1 + γ_iΔλ), with the return
/// along ξ* = s_tr − Σ α_i(t)/(1 + γ_iΔλ), parallel to the final relative stress, and the
/// scalar equation q(ξ*) − (3G + Σ C_i/(1 + γ_iΔλ))·Δλ = H(ε̃^p + Δλ) solved by a safeguarded
/// Newton iteration (after Kobayashi and Ohno, Int. J. Numer. Meth. Eng. 53 (2002) 2217, and
/// de Souza Neto, Perić and Owen, Computational Methods for Plasticity, 2008, section 7.6.4).
/// The tangent is the consistent one but for its nonsymmetric part, −(2GΔλ·3/(2q*))·(P a')⊗N
/// with a' = Σ γ_iα_i(t)/(1 + γ_iΔλ)², which the symmetric solvers cannot take: newton
/// converges a little slower than quadratically while the back stresses saturate. `alpha`
/// returns the α_i at t+Δt.
ReturnMapping armstrong_frederick_return(const ElasticConstants& k, const StepCurve& curve,
                                         std::span<const BackStressLaw> laws, const Voigt& sigma0,
                                         std::span<const Voigt> alpha0, const Voigt& d_eps_ep,
                                         std::span<Voigt> alpha);

/// The point law (point_law.hpp) of `plasticity: {..., kinematic: [{C, gamma}, ...]}`: the
/// isotropic curve as given (`perfect` for none) and the back stresses (Chaboche's sum of
/// Armstrong–Frederick ones; all γ = 0 is Prager's linear rule, H_k(T) = ΣC_i(T)); newton
/// only. Its state is the whole back stress α = Σα_i (`back_stress`, 6), then α_2 .. α_m
/// (`back_stress_2`, ...).
class KinematicLaw final : public PointLaw {
 public:
  explicit KinematicLaw(std::vector<PropertyTable> c, std::vector<PropertyTable> gamma = {});
  std::span<const LawVariable> variables() const override;
  ReturnMapping update(const ElasticConstants& k, const StepCurve& curve, const Voigt& sigma0,
                       const Voigt& d_mech, std::span<const double> state0,
                       std::span<double> state1) const override;
  Voigt relative_stress(const Voigt& sigma, std::span<const double> state) const override {
    return sigma - Eigen::Map<const Voigt>(state.data());
  }
  /// H_k at temperature T.
  double modulus(double T) const;

 private:
  std::vector<PropertyTable> c_, gamma_;
  bool linear_ = true;  ///< every γ is 0: Prager's rule, one back stress of modulus ΣC_i
  std::vector<LawVariable> variables_;
};

/// Its declaration: the key `kinematic`, a list of {C (Pa), gamma (1)}.
LawDeclaration kinematic_law_declaration();

}  // namespace hencky
