#include "material/kinematic.hpp"

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

}  // namespace hencky
