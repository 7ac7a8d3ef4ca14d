#pragma once
// The hardening curve of a von Mises material (report 1.17-1.18), converted once from any input
// form of the case file to the plastic form H: σ̃ = H(ε̃^p, T), with ε̃^p the equivalent plastic
// strain (= the uniaxial plastic strain under uniaxial stress, since c_ε̃ = 4/9). The
// formulation's two evaluations follow from H and the shear modulus at the same temperature:
//
//   Φ: σ̃ = Φ(ε̃^{e+p}, T)  where  ε̃^{e+p} = ε̃^p + H(ε̃^p, T) / (3G)   (the curve, (1.18))
//   F: ε̃^{e+p} = F(σ̃, T) = σ̃ / (3G) + H⁻¹(σ̃, T)                       (its inverse)
//
// with the elastic line σ̃ = 3G·ε̃^{e+p} below the yield point (tan β^e = 3G, (2.12)).
//
// Tables: linear between points; beyond the last point the stress stays at the last value
// (perfectly plastic, as CalculiX and Abaqus do) and a warning is logged once per material.
// Between tables of different temperatures H is interpolated linearly in T at fixed ε̃^p; outside
// the temperature range the end table is used (a warning, as for E, ν, α).
//
// Evaluations are pure and thread-safe: the element loops call them for every point.
#include <vector>

#include "core/log.hpp"
#include "spec/case.hpp"

namespace hencky {

class Hardening {
 public:
  /// A value of a curve and its slope.
  struct Point {
    double value = 0;
    double slope = 0;
  };

  /// Converts and checks the curve of `spec` (the material's E and ν are needed to bring
  /// uniaxial and intensity tables to the plastic form, at each table's temperature).
  /// Throws InputError naming the table and point: a strain that does not increase, a first
  /// point that is not on the elastic line (uniaxial, intensity) or whose plastic strain is
  /// not 0 (plastic), a point below the elastic line's yield, negative stresses, a slope
  /// dσ̃/dε̃^p ≤ −3G (the curve would turn back in ε̃^{e+p}: Φ is not a function).
  Hardening(const PlasticitySpec& spec, const PropertyTable& E, const PropertyTable& nu);

  /// H(ε̃^p, T) and dH/dε̃^p (the slope to the right at a table's breakpoints). eps_p >= 0
  /// (a negative value is taken as 0). For Ramberg-Osgood H(0) = 0 and the slope there is +inf.
  Point plastic(double eps_p, double T) const;

  /// Initial yield stress H(0, T).
  double yield(double T) const { return plastic(0.0, T).value; }

  /// Φ(ε̃^{e+p}, T) and dΦ/dε̃^{e+p}, for 3G = three_g at T. Below the yield intensity (and for
  /// negative arguments) the elastic line 3G·ε̃ with slope 3G. Slopes are taken to the right
  /// (towards larger ε̃): at the yield point itself and at breakpoints the slope of the curve
  /// beyond it.
  Point phi(double eps_ep, double T, double three_g) const;

  /// F(σ̃, T) and dF/dσ̃. Below the yield stress (and for negative σ̃) σ̃/(3G), slope 1/(3G).
  /// Above the highest stress the curve reaches (perfect plasticity, the flat end of a table,
  /// a softening curve's peak), value and slope are +inf: the strain form cannot be used there.
  /// Where the curve first reaches σ̃, F is the smallest such ε̃ and the slope is taken to the
  /// right (+inf at the start of a flat or falling part, e.g. at σ̃ = yield for perfect
  /// plasticity).
  Point f(double sigma, double T, double three_g) const;

  /// Largest stress the curve reaches at T (+inf for a curve that hardens without bound).
  double max_stress(double T) const;

  /// The largest ε̃^p of the tables (0 for analytic forms): beyond it a table is flat.
  double table_end() const { return table_end_; }

  /// Warns once (per material name) when the temperature range [T_min, T_max] leaves the
  /// curve's tables, or when an equivalent plastic strain beyond table_end() was reached.
  void warn_outside(const std::string& material, double T_min, double T_max, double eps_p_max,
                    Log& log) const;

 private:
  // Tables in plastic form: per temperature, eps_p[0] = 0 < eps_p[1] < ..., stress[i], and
  // slope[i] = dH/dε̃^p on [eps_p[i], eps_p[i+1]) (0 for the last point: flat beyond it).
  struct PlasticTable {
    double temperature;
    std::vector<double> eps_p, stress, slope;
  };
  // The tables in use at a temperature: H = (1 − s)·H_a + s·H_b (a == b, s = 0 outside the
  // range of temperatures or with one table).
  struct Bracket {
    std::size_t a = 0, b = 0;
    double s = 0;
  };
  Bracket bracket(double T) const;
  void convert_tables(const CurveSpec& curve, const PropertyTable& E, const PropertyTable& nu);

  CurveSpec::Kind kind_;
  std::vector<PlasticTable> tables_;
  PropertyTable yield_, hardening_;
  double ro_E_ = 0, ro_alpha_ = 0, ro_n_ = 0;
  double table_end_ = 0;
};

}  // namespace hencky
