#pragma once
// What the point laws of the schemes share (schemes.cpp: newton, variable-stiffness;
// fixed_matrix_schemes.cpp: the initial strains and stresses): the iterate seen along its flow
// direction Z, the curve's secant over the step, the `-stiffness` start slope of a point that
// unloads, and the stress and memory of an iterate from its plastic multiplier. Internal to
// those two files; the interface of the schemes is solve/schemes.hpp.
#include <memory>

#include "solve/schemes.hpp"

namespace hencky::scheme_law {

/// The size below which an increment of ε̃^{e+p} is round-off relative to ε̃^{e+p}(t) = `eps0`
/// (a purely volumetric increment, e.g. a thermal predictor, has ZᵀDx = 0 to round-off).
double strain_roundoff(const PointStep& ps, double eps0);

/// The secant of the curve over the step, (Φ(ε̃ + Δε̃) − σ̃)/Δε̃ with Φ(ε̃ + Δε̃) = `phi_value`:
/// tan β* of (2.33) and tan β** of (2.42). It is a difference of two numbers of the size of σ̃
/// divided by Δε̃: for an increment at round-off level it is noise of any sign and size (which
/// made D̃ indefinite at thermal predictors); its limit there is the curve's slope.
double stress_secant(const PointStep& ps, double eps0, double q0, double xt, double phi_value,
                     bool right);

/// What the five schemes of the report share once an iterate is evaluated along Z: the point
/// moves along the flow direction z of the step, from ε̃^{e+p}(t) = eps0 by xt.
struct AlongZ {
  Voigt z;
  double q0 = 0;    ///< σ̃(t) seen along Z
  double eps0 = 0;  ///< ε̃^{e+p}(t)
  double xt = 0;    ///< Δε̃^{e+p}_k = ZᵀDx / 3G
  Voigt dx;         ///< D x
};

/// The iterate seen along the direction z (a.dx already set).
void take_direction(AlongZ& a, const Voigt& z, const PointStep& ps, const Voigt& sigma0);

/// The iterate x seen along the direction of its trial stress σ(t) + Dx, as the radial return
/// takes it: Z = Mσ/σ̃ of the answer, so the answer lies on the yield surface and is newton's
/// (backward Euler) to the tolerance on any path, with every scheme. The report's (2.10) takes
/// Z(t) = Mσ(t)/σ̃(t), fixed over the step: the stress lands on the curve along Z(t) and its
/// part across Z(t) stays elastic, so where the stress turns within a step the answer lies
/// above the yield surface (the ball indentation's contact edge: von Mises 1.3-7.7 times the
/// yield stress at t = 1 with variable-stiffness, its ball force 26 % above newton's; the
/// initial strains 23-30 % from newton's dent). Z(t) remains the direction of the `-stiffness`
/// schemes' matrix D̃(β*_0) (PointStep::z).
AlongZ along_z(const ElasticConstants& k1, const PointStep& ps, const Voigt& sigma0,
               const Voigt& x);

/// The `-stiffness` schemes (2.38)-(2.40), (2.44)-(2.46) fix tan β* at "the slope at the start of
/// the step", which for a point that was flowing depends on the direction the step takes: the
/// curve's loading slope if it keeps flowing, the elastic line 3G if it unloads (elastic
/// unloading). The report leaves the choice open; the loading slope is taken at the start, and
/// once the first iterates (the predictor, and the first solve: the matrix may then be refactored
/// once more) show the point unloading, 3G. With the loading slope kept, the fixed-matrix
/// iteration at an unloading point multiplies its error by 1 − 3G/tan β*_0 and diverges.
/// Unloading is seen along the direction of the start of the step, Z(t) (the matrix's): the
/// iterate's own direction turns over with a trial stress that passes through zero. A decrease
/// at round-off level is not unloading.
/// Returns true when it switched.
bool start_slope_on_unloading(const PointStep& ps, PointIteration& it, const AlongZ& a,
                              const Voigt& sigma0);

/// The stress and plastic state of the iterate from the plastic multiplier `lambda` along Z,
/// and the scheme's memory for the next iteration (ds: Δσ̃_k; new_tan: tan β of k+1; e0:
/// the initial strain of k+1).
void finish(const ElasticConstants& k1, const PointStep& ps, const PointIteration& it,
            const Voigt& sigma0, const AlongZ& a, double lambda, double ds, double new_tan,
            const Voigt& e0, PointUpdate& u);

/// The schemes with a matrix fixed within the step (fixed_matrix_schemes.cpp), for make_scheme:
/// schemes 2 and 3 (initial strains, relaxed by `omega`) and 4 and 5 (initial stresses), with
/// the elastic matrix or, `stiffness`, the start-of-step tangent.
std::unique_ptr<Scheme> make_initial_strain(bool stiffness, double omega);
std::unique_ptr<Scheme> make_initial_stress(bool stiffness);

}  // namespace hencky::scheme_law
