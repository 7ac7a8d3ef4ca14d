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

std::span<const LawVariable> KinematicLaw::variables() const {
  static const std::array<LawVariable, 1> v = {LawVariable{"back_stress", 6}};
  return v;
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
  const KinematicReturn r =
      kinematic_return(k, curve, modulus(curve.temperature), sigma0, alpha0, d_mech);
  Eigen::Map<Voigt>(state1.data()) = r.alpha;
  return r.mapping;
}

LawDeclaration kinematic_law_declaration() {
  LawDeclaration d;
  d.name = "kinematic";
  d.keys = {
      LawKey{"kinematic", {"C", "gamma"}, "C in Pa (dα/dε^p, the back stress's modulus), gamma 1"}};
  d.make = [](const PlasticitySpec& spec) -> std::shared_ptr<const PointLaw> {
    const auto& groups = spec.law.keys.at("kinematic");
    std::vector<PropertyTable> c;
    for (const auto& g : groups) {
      const PropertyTable& gamma = g.at("gamma");
      for (double v : gamma.value)
        if (v != 0)
          throw InputError(gamma.where,
                           fmt::format("gamma = {:g}: only linear kinematic hardening (Prager, "
                                       "gamma: 0) is available; Armstrong-Frederick back "
                                       "stresses (gamma > 0) are not yet",
                                       v));
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
    return std::make_shared<KinematicLaw>(std::move(c));
  };
  return d;
}

}  // namespace hencky
