// The shared steps of the schemes' point laws (solve/scheme_law.hpp).
#include "solve/scheme_law.hpp"

#include <algorithm>
#include <cmath>

namespace hencky::scheme_law {

double strain_roundoff(const PointStep& ps, double eps0) {
  return 1e-8 * std::max(std::abs(eps0), ps.curve.eps_yield_now);
}

double stress_secant(const PointStep& ps, double eps0, double q0, double xt, double phi_value,
                     bool right) {
  return std::abs(xt) > strain_roundoff(ps, eps0) ? (phi_value - q0) / xt
                                                  : ps.curve.phi(eps0, right).slope;
}

void take_direction(AlongZ& a, const Voigt& z, const PointStep& ps, const Voigt& sigma0) {
  a.z = z;
  a.q0 = a.z.dot(sigma0);
  a.eps0 = ps.curve.eps_p + a.q0 / ps.curve.three_g;
  a.xt = a.z.dot(a.dx) / ps.curve.three_g;
}

AlongZ along_z(const ElasticConstants& k1, const PointStep& ps, const Voigt& sigma0,
               const Voigt& x) {
  AlongZ a;
  a.dx = Tangent{}.times(k1, x);
  take_direction(a, flow_direction(sigma0 + a.dx), ps, sigma0);
  return a;
}

bool start_slope_on_unloading(const PointStep& ps, PointIteration& it, const AlongZ& a,
                              const Voigt& sigma0) {
  if (!ps.flowing || !ps.curve.elastic_unloading || it.k > 1 || it.tan_start == ps.curve.three_g)
    return false;
  const double three_g = ps.curve.three_g;
  const double eps0 = ps.curve.eps_p + ps.z.dot(sigma0) / three_g;
  if (!(ps.z.dot(a.dx) / three_g < -strain_roundoff(ps, eps0))) return false;
  it.tan_start = ps.curve.three_g;
  return true;
}

void finish(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
            const Voigt& sigma0, const AlongZ& a, double lambda, double ds, double new_tan,
            const Voigt& e0, PointUpdate& u) {
  // Round-off on the elastic line is not plastic flow.
  if (std::abs(lambda) <= 1e-12 * std::max(std::abs(a.eps0 + a.xt), ps.curve.eps_yield_now))
    lambda = 0;
  u.z = a.z;
  u.d_lambda = lambda;
  u.plastic = lambda != 0;
  u.sigma = sigma0 + a.dx - lambda * Tangent{}.times(k1, a.z);  // σ(t) + D(x − Zλ)
  u.eps_ep = a.eps0 + a.xt;
  remember_iterate(u, it, a.xt, ds, new_tan);
  u.next.e0 = e0;
}

}  // namespace hencky::scheme_law
