#pragma once
// Linear kinematic hardening (Prager) combined with the isotropic curve: the yield surface
// σ̃(σ − α) = H(ε̃^p, T) moves with the back stress α, dα = (2/3)·H_k·dε^p (a deviatoric
// stress), so that a uniaxial bar that yielded in tension to a plastic strain ε_p yields again in
// compression at σ = H_k·ε_p − σ_y (the Bauschinger effect) with its elastic range 2σ_y kept
// (for a perfectly plastic isotropic part). The return is the radial return of the stress
// relative to α (radial_return with H_k), after Simo and Hughes, Computational Inelasticity,
// 1998, section 3.3 (J2 with combined linear hardening). A pure function, as radial_return.
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

/// The point law (point_law.hpp) of `plasticity: {..., kinematic: [{C, gamma: 0}, ...]}`: the
/// isotropic curve as given (`perfect` for none) and H_k(T) = ΣC_i(T); newton only. Its state
/// is the back stress α (`back_stress`, 6).
class KinematicLaw final : public PointLaw {
 public:
  explicit KinematicLaw(std::vector<PropertyTable> c) : c_(std::move(c)) {}
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
  std::vector<PropertyTable> c_;
};

/// Its declaration: the key `kinematic`, a list of {C (Pa), gamma (1)}.
LawDeclaration kinematic_law_declaration();

}  // namespace hencky
