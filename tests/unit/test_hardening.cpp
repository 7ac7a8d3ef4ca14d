// The hardening curve (material/hardening.hpp): every input form reproduces its own points on a
// uniaxial stress path, Φ and F are inverse of each other, their slopes are the derivatives,
// tables are interpolated in temperature at fixed plastic strain and continue flat, and every
// bad curve is refused with a message that names the table and the point.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "material/hardening.hpp"

namespace hencky {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

PropertyTable constant(double v) {
  PropertyTable p;
  p.value = {v};
  return p;
}

PropertyTable over_temperature(std::vector<double> T, std::vector<double> v,
                               const std::string& key = "") {
  PropertyTable p;
  p.temperature = std::move(T);
  p.value = std::move(v);
  p.where.key = key;
  return p;
}

// E(T) over two temperatures, ν constant: each table is converted with its own E and 3G.
const PropertyTable E_T = over_temperature({20, 500}, {2.1e11, 1.7e11});
const PropertyTable nu_c = constant(0.3);
double three_g(double T) {
  return 3 * E_T(T) / (2 * (1 + nu_c(T)));
}

std::string table_key(std::size_t j) {
  return "materials[0].plasticity.curve.table[" + std::to_string(j) + "]";
}

/// A table as the case reader makes it, with locations: table j on line 10 + j, point i at
/// column 20 + 10 i.
CurveSpec::Table table(std::size_t j, double T, std::vector<double> strain,
                       std::vector<double> stress) {
  CurveSpec::Table t;
  t.temperature = T;
  t.strain = std::move(strain);
  t.stress = std::move(stress);
  t.where = SourceLocation{"case.yaml", 10 + static_cast<int>(j), 11, table_key(j)};
  for (std::size_t i = 0; i < t.strain.size(); ++i)
    t.point_where.push_back(SourceLocation{"case.yaml", 10 + static_cast<int>(j),
                                           20 + 10 * static_cast<int>(i),
                                           table_key(j) + ".strain[" + std::to_string(i) + "]"});
  return t;
}

PlasticitySpec table_spec(CurveSpec::Form form, std::vector<CurveSpec::Table> tables) {
  PlasticitySpec s;
  s.curve.kind = CurveSpec::Kind::table;
  s.curve.form = form;
  s.curve.tables = std::move(tables);
  s.curve.where.key = "materials[0].plasticity.curve";
  return s;
}

PlasticitySpec analytic_spec(CurveSpec::Kind kind, PropertyTable yield,
                             PropertyTable hardening = {}) {
  PlasticitySpec s;
  s.curve.kind = kind;
  s.curve.yield = std::move(yield);
  s.curve.hardening = std::move(hardening);
  return s;
}

PlasticitySpec ramberg_osgood_spec(PropertyTable yield, double E, double alpha, double n) {
  PlasticitySpec s = analytic_spec(CurveSpec::Kind::ramberg_osgood, std::move(yield));
  s.curve.ro_E = E;
  s.curve.ro_alpha = alpha;
  s.curve.ro_n = n;
  return s;
}

// The three table forms of one set of data, two temperatures each.
PlasticitySpec uniaxial_tables() {
  return table_spec(CurveSpec::Form::uniaxial,
                    {table(0, 20, {240e6 / 2.1e11, 0.01, 0.05, 0.1}, {240e6, 260e6, 300e6, 310e6}),
                     table(1, 500, {150e6 / 1.7e11, 0.005, 0.08}, {150e6, 180e6, 200e6})});
}
PlasticitySpec plastic_tables() {
  return table_spec(CurveSpec::Form::plastic, {table(0, 20, {0, 0.01, 0.05}, {240e6, 260e6, 300e6}),
                                               table(1, 500, {0, 0.02}, {150e6, 200e6})});
}
PlasticitySpec intensity_tables() {
  return table_spec(CurveSpec::Form::intensity,
                    {table(0, 20, {240e6 / three_g(20), 0.02, 0.06}, {240e6, 270e6, 320e6}),
                     table(1, 500, {150e6 / three_g(500), 0.01}, {150e6, 170e6})});
}

/// The message of the InputError that building the curve throws; fails the test when none.
std::string error(const PlasticitySpec& s, const PropertyTable& E = E_T,
                  const PropertyTable& nu = nu_c) {
  try {
    Hardening h(s, E, nu);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

void expect_error(const PlasticitySpec& s, std::initializer_list<std::string> parts,
                  const PropertyTable& E = E_T) {
  const std::string m = error(s, E);
  for (const auto& p : parts)
    EXPECT_NE(m.find(p), std::string::npos) << "missing \"" << p << "\" in:\n" << m;
}

// ---------------------------------------------------------------------------------------------
// The input curve back on a uniaxial stress path

/// Under uniaxial stress σ̃ = σ and ε̃^p = ε^p: each input point (ε, σ) of the table at its own
/// temperature must come back exactly from Φ, F and H. `plastic_of` converts the point's
/// strain to its plastic strain as the form defines it.
void expect_points_reproduced(
    const Hardening& h, const PlasticitySpec& s,
    const std::function<double(double eps, double sig, double T)>& plastic_of) {
  for (const auto& t : s.curve.tables) {
    const double T = t.temperature, g3 = three_g(T);
    for (std::size_t i = 0; i < t.strain.size(); ++i) {
      SCOPED_TRACE("T = " + std::to_string(T) + ", point " + std::to_string(i));
      const double sig = t.stress[i];
      const double ep = i == 0 ? 0.0 : plastic_of(t.strain[i], sig, T);
      const double eps_ep = ep + sig / g3;  // ε̃^{e+p}, (1.18)
      EXPECT_NEAR(h.plastic(ep, T).value, sig, 1e-12 * sig);
      EXPECT_NEAR(h.phi(eps_ep, T, g3).value, sig, 1e-12 * sig);
      EXPECT_NEAR(h.f(sig, T, g3).value, eps_ep, 1e-12 * eps_ep);
    }
  }
}

TEST(Hardening, UniaxialTableReproducesItsPoints) {
  const PlasticitySpec s = uniaxial_tables();
  const Hardening h(s, E_T, nu_c);
  // ε^p = ε − σ/E(T_table), and the total uniaxial strain is σ/E + ε^p again
  expect_points_reproduced(h, s,
                           [](double eps, double sig, double T) { return eps - sig / E_T(T); });
  const double ep = 0.05 - 300e6 / 2.1e11;
  EXPECT_DOUBLE_EQ(300e6 / 2.1e11 + ep, 0.05);
  EXPECT_DOUBLE_EQ(h.table_end(), 0.1 - 310e6 / 2.1e11);
}

TEST(Hardening, PlasticTableReproducesItsPoints) {
  const PlasticitySpec s = plastic_tables();
  const Hardening h(s, E_T, nu_c);
  expect_points_reproduced(h, s, [](double eps, double, double) { return eps; });
  EXPECT_DOUBLE_EQ(h.table_end(), 0.05);
}

TEST(Hardening, IntensityTableReproducesItsPoints) {
  const PlasticitySpec s = intensity_tables();
  const Hardening h(s, E_T, nu_c);
  // ε̃^p = ε̃ − σ̃/3G(T_table)
  expect_points_reproduced(h, s,
                           [](double eps, double sig, double T) { return eps - sig / three_g(T); });
  for (const auto& t : s.curve.tables)  // Φ(ε̃) = σ̃ directly on the given intensities
    for (std::size_t i = 0; i < t.strain.size(); ++i)
      EXPECT_NEAR(h.phi(t.strain[i], t.temperature, three_g(t.temperature)).value, t.stress[i],
                  1e-12 * t.stress[i]);
}

TEST(Hardening, AnalyticFormsReproduceTheirCurves) {
  const PropertyTable yield_T = over_temperature({20, 500}, {240e6, 150e6});
  const PropertyTable hard_T = over_temperature({20, 500}, {2e9, 1e9});
  for (double T : {0.0, 20.0, 140.0, 260.0, 500.0, 700.0}) {
    SCOPED_TRACE("T = " + std::to_string(T));
    const double g3 = three_g(T), y = yield_T(T), hh = hard_T(T);
    // perfect: H = yield(T)
    const Hardening perfect(analytic_spec(CurveSpec::Kind::perfect, yield_T), E_T, nu_c);
    EXPECT_DOUBLE_EQ(perfect.yield(T), y);
    for (double ep : {0.0, 0.001, 0.3}) {
      EXPECT_DOUBLE_EQ(perfect.plastic(ep, T).value, y);
      EXPECT_NEAR(perfect.phi(ep + y / g3, T, g3).value, y, 1e-12 * y);
    }
    // linear: H = yield(T) + hardening(T)·ε̃^p
    const Hardening linear(analytic_spec(CurveSpec::Kind::linear, yield_T, hard_T), E_T, nu_c);
    for (double ep : {0.0, 0.001, 0.02, 0.3}) {
      const double sig = y + hh * ep;
      EXPECT_NEAR(linear.plastic(ep, T).value, sig, 1e-12 * sig);
      EXPECT_NEAR(linear.phi(ep + sig / g3, T, g3).value, sig, 1e-12 * sig);
      EXPECT_NEAR(linear.f(sig, T, g3).value, ep + sig / g3, 1e-12 * (ep + sig / g3));
    }
    // Ramberg-Osgood: uniaxial ε = σ/E + α(σ_y/E)(σ/σ_y)^n, plastic part ε̃^p
    const double Ero = 2.0e11, alpha = 0.002, n = 7.5;
    const Hardening ro(ramberg_osgood_spec(yield_T, Ero, alpha, n), E_T, nu_c);
    for (double sig : {1e6, 50e6, 0.9 * y, y, 1.3 * y, 2.5 * y}) {
      const double ep = alpha * y / Ero * std::pow(sig / y, n);
      EXPECT_NEAR(ro.plastic(ep, T).value, sig, 1e-12 * sig);
      EXPECT_NEAR(ro.phi(ep + sig / g3, T, g3).value, sig, 1e-13 * sig);
      EXPECT_NEAR(ro.f(sig, T, g3).value, ep + sig / g3, 1e-13 * (ep + sig / g3));
    }
  }
}

TEST(Hardening, RambergOsgoodStartsAtZeroWithInfiniteSlope) {
  const Hardening ro(ramberg_osgood_spec(constant(240e6), 2e11, 0.002, 10), E_T, nu_c);
  EXPECT_EQ(ro.plastic(0, 20).value, 0.0);
  EXPECT_EQ(ro.plastic(0, 20).slope, inf);
  EXPECT_EQ(ro.yield(20), 0.0);
  EXPECT_EQ(ro.max_stress(20), inf);
  EXPECT_EQ(ro.table_end(), 0.0);
  const double g3 = three_g(20);
  // a tiny strain is almost elastic: the plastic part α(σ/σ_y)^n σ_y/E is negligible
  const Hardening::Point p = ro.phi(1e-6, 20, g3);
  EXPECT_NEAR(p.value, g3 * 1e-6, 1e-12 * g3 * 1e-6);
  EXPECT_NEAR(p.slope, g3, 1e-9 * g3);
  EXPECT_EQ(ro.phi(0, 20, g3).slope, g3);
  EXPECT_EQ(ro.phi(-1e-3, 20, g3).value, -g3 * 1e-3);
  // deep in the plastic range Newton still converges (n large, strain large)
  const Hardening steep(ramberg_osgood_spec(constant(240e6), 2e11, 0.5, 40), E_T, nu_c);
  const double s = steep.phi(0.5, 20, g3).value;
  EXPECT_NEAR(steep.f(s, 20, g3).value, 0.5, 1e-14 * 0.5);
}

// ---------------------------------------------------------------------------------------------
// Φ and F, slopes, temperature interpolation

/// Every curve of the tests, by name.
std::vector<std::pair<std::string, Hardening>> all_curves() {
  const PropertyTable yield_T = over_temperature({20, 500}, {240e6, 150e6});
  std::vector<std::pair<std::string, Hardening>> c;
  c.emplace_back("uniaxial", Hardening(uniaxial_tables(), E_T, nu_c));
  c.emplace_back("plastic", Hardening(plastic_tables(), E_T, nu_c));
  c.emplace_back("intensity", Hardening(intensity_tables(), E_T, nu_c));
  c.emplace_back(
      "softening table",
      Hardening(table_spec(CurveSpec::Form::plastic,
                           {table(0, 20, {0, 0.01, 0.03, 0.06}, {240e6, 300e6, 200e6, 260e6})}),
                E_T, nu_c));
  c.emplace_back("perfect", Hardening(analytic_spec(CurveSpec::Kind::perfect, yield_T), E_T, nu_c));
  c.emplace_back("linear", Hardening(analytic_spec(CurveSpec::Kind::linear, yield_T,
                                                   over_temperature({20, 500}, {2e9, 1e9})),
                                     E_T, nu_c));
  c.emplace_back(
      "linear softening",
      Hardening(analytic_spec(CurveSpec::Kind::linear, yield_T, constant(-4e9)), E_T, nu_c));
  c.emplace_back("ramberg_osgood",
                 Hardening(ramberg_osgood_spec(yield_T, 2e11, 0.002, 7.5), E_T, nu_c));
  return c;
}

const double temperatures[] = {0.0, 20.0, 140.0, 260.0, 500.0, 650.0};

TEST(Hardening, PhiAndFAreInverse) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (const auto& [name, h] : all_curves()) {
    for (double T : temperatures) {
      SCOPED_TRACE(name + " at T = " + std::to_string(T));
      const double g3 = three_g(T);
      for (int k = 0; k < 200; ++k) {
        // Φ then F: back to ε̃ wherever Φ rises (on a flat or falling part F gives the
        // smallest ε̃ with that stress, or +inf beyond the peak)
        const double eps = 0.12 * u(gen);
        const Hardening::Point s = h.phi(eps, T, g3);
        if (s.slope > 0 && s.value >= h.max_stress(T) * (1 - 1e-12)) continue;
        if (s.slope > 0) {
          bool before_peak = true;  // no higher stress reached earlier
          for (double e = 0; e < eps; e += eps / 200)
            before_peak = before_peak && h.phi(e, T, g3).value < s.value;
          if (before_peak) {
            EXPECT_NEAR(h.f(s.value, T, g3).value, eps, 1e-11 * eps) << "eps " << eps;
          }
        }
        // F then Φ: back to σ̃ below the largest stress
        const double m = std::min(h.max_stress(T), 600e6);
        const double sig = m * u(gen);
        const Hardening::Point e = h.f(sig, T, g3);
        ASSERT_TRUE(std::isfinite(e.value)) << "sigma " << sig;
        EXPECT_NEAR(h.phi(e.value, T, g3).value, sig, 1e-11 * sig) << "sigma " << sig;
      }
      if (std::isfinite(h.max_stress(T))) {  // above the peak F is +inf, value and slope
        const Hardening::Point e = h.f(h.max_stress(T) * 1.001, T, g3);
        EXPECT_EQ(e.value, inf);
        EXPECT_EQ(e.slope, inf);
      }
    }
  }
}

/// Central differences, away from kinks (for piecewise-linear curves a kink shows as forward
/// and backward differences that disagree).
void expect_slopes(const std::string& what, const std::function<Hardening::Point(double)>& fn,
                   double lo, double hi, bool smooth) {
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(lo, hi);
  int checked = 0;
  for (int k = 0; k < 300; ++k) {
    const double x = u(gen), d = 1e-7 * x;
    const Hardening::Point p = fn(x);
    const double vp = fn(x + d).value, vm = fn(x - d).value;
    if (!std::isfinite(p.value) || !std::isfinite(vp) || !std::isfinite(vm)) continue;
    const double fwd = (vp - p.value) / d, bwd = (p.value - vm) / d;
    const double scale = std::abs(fwd) + std::abs(bwd) + 1e-30;
    if (!smooth && std::abs(fwd - bwd) > 1e-5 * scale) continue;  // a kink within ±d
    const double central = (vp - vm) / (2 * d);
    EXPECT_NEAR(p.slope, central, 2e-5 * scale) << what << " at " << x;
    ++checked;
  }
  EXPECT_GT(checked, 200) << what;
}

TEST(Hardening, SlopesAreDerivatives) {
  // Not a structured binding: clang before 16 cannot capture one in the lambdas below.
  for (const auto& curve : all_curves()) {
    const std::string& name = curve.first;
    const Hardening& h = curve.second;
    const bool smooth = name == "ramberg_osgood";
    for (double T : temperatures) {
      SCOPED_TRACE(name + " at T = " + std::to_string(T));
      const double g3 = three_g(T);
      expect_slopes(
          "H", [&](double p) { return h.plastic(p, T); }, 1e-5, 0.12, smooth);
      expect_slopes(
          "Phi", [&](double e) { return h.phi(e, T, g3); }, 1e-5, 0.12, smooth);
      const double m = std::min(h.max_stress(T), 600e6);
      expect_slopes(
          "F", [&](double s) { return h.f(s, T, g3); }, 1e-3 * m, 0.999 * m, smooth);
      // the slopes of Φ and F follow from H': 3G·H'/(3G + H') and 1/(3G) + 1/H'
      for (double p : {0.003, 0.017, 0.04, 0.07}) {
        const Hardening::Point hp = h.plastic(p, T);
        if (hp.value <= 0) continue;
        const double eps = p + hp.value / g3;
        const Hardening::Point ph = h.phi(eps, T, g3);
        EXPECT_NEAR(ph.value, hp.value, 1e-9 * hp.value);
        EXPECT_NEAR(ph.slope, g3 * hp.slope / (g3 + hp.slope), 1e-9 * g3);
        if (hp.slope > 0 && std::abs(h.f(hp.value, T, g3).value - eps) < 1e-12 * eps) {
          EXPECT_NEAR(h.f(hp.value, T, g3).slope, 1 / g3 + 1 / hp.slope, 1e-9 / hp.slope);
        }
      }
    }
  }
}

TEST(Hardening, ElasticLineBelowYield) {
  for (const auto& [name, h] : all_curves()) {
    for (double T : temperatures) {
      SCOPED_TRACE(name + " at T = " + std::to_string(T));
      const double g3 = three_g(T), y = h.yield(T);
      for (double s : {-100e6, 0.0, 0.5 * y, 0.999 * y}) {
        const Hardening::Point e = h.f(s, T, g3);
        EXPECT_DOUBLE_EQ(e.value, s / g3);
        EXPECT_DOUBLE_EQ(e.slope, 1 / g3);
        if (name == "ramberg_osgood") continue;  // no elastic range: yield is 0
        const Hardening::Point p = h.phi(s / g3, T, g3);
        EXPECT_DOUBLE_EQ(p.value, s);
        EXPECT_DOUBLE_EQ(p.slope, g3);
      }
    }
  }
}

TEST(Hardening, TablesAreInterpolatedInTemperatureAtFixedPlasticStrain) {
  // T = 20: ε^p [0, 0.01, 0.05] σ [240, 260, 300] MPa; T = 500: ε^p [0, 0.02] σ [150, 200] MPa
  const Hardening h(plastic_tables(), E_T, nu_c);
  // T = 260 is halfway. ε^p = 0.015: 265 and 187.5 -> 226.25; slopes 1e9 and 2.5e9 -> 1.75e9
  EXPECT_NEAR(h.plastic(0.015, 260).value, 226.25e6, 1e-6);
  EXPECT_NEAR(h.plastic(0.015, 260).slope, 1.75e9, 1e-3);
  // ε^p = 0.03: 280 and the flat 200 -> 240; slope 0.5·1e9
  EXPECT_NEAR(h.plastic(0.03, 260).value, 240e6, 1e-6);
  EXPECT_NEAR(h.plastic(0.03, 260).slope, 0.5e9, 1e-3);
  // T = 140 is a quarter: ε^p = 0.005: 0.75·250 + 0.25·162.5 = 228.125
  EXPECT_NEAR(h.plastic(0.005, 140).value, 228.125e6, 1e-6);
  EXPECT_NEAR(h.yield(140), 0.75 * 240e6 + 0.25 * 150e6, 1e-6);
  // outside the temperatures the end tables
  EXPECT_DOUBLE_EQ(h.plastic(0.005, -50).value, 250e6);
  EXPECT_DOUBLE_EQ(h.plastic(0.005, 900).value, 162.5e6);
  // Φ and F walk both tables' breakpoints: the same numbers through the intensity
  const double g3 = three_g(260), eps = 0.015 + 226.25e6 / g3;
  EXPECT_NEAR(h.phi(eps, 260, g3).value, 226.25e6, 1e-6);
  EXPECT_NEAR(h.phi(eps, 260, g3).slope, g3 * 1.75e9 / (g3 + 1.75e9), 1e-3);
  EXPECT_NEAR(h.f(226.25e6, 260, g3).value, eps, 1e-15);
  EXPECT_NEAR(h.f(240e6, 260, g3).value, 0.03 + 240e6 / g3, 1e-15);
  // and at a quarter: slopes 2e9 and 2.5e9 -> 2.125e9
  const double g3q = three_g(140), eps_q = 0.005 + 228.125e6 / g3q;
  EXPECT_NEAR(h.phi(eps_q, 140, g3q).value, 228.125e6, 1e-6);
  EXPECT_NEAR(h.phi(eps_q, 140, g3q).slope, g3q * 2.125e9 / (g3q + 2.125e9), 1e-3);
  EXPECT_NEAR(h.f(228.125e6, 140, g3q).value, eps_q, 1e-15);
  EXPECT_NEAR(h.f(228.125e6, 140, g3q).slope, 1 / g3q + 1 / 2.125e9, 1e-24);
  // largest stress at 260: at ε^p = 0.05, (300 + 200)/2
  EXPECT_DOUBLE_EQ(h.max_stress(260), 250e6);
  EXPECT_DOUBLE_EQ(h.max_stress(20), 300e6);
}

TEST(Hardening, ConstantBeyondTheLastPoint) {
  const Hardening h(plastic_tables(), E_T, nu_c);
  const double g3 = three_g(20);
  for (double p : {0.05, 0.07, 1.0}) {
    EXPECT_DOUBLE_EQ(h.plastic(p, 20).value, 300e6);
    EXPECT_EQ(h.plastic(p, 20).slope, 0.0);
    EXPECT_DOUBLE_EQ(h.phi(p + 300e6 / g3, 20, g3).value, 300e6);
    EXPECT_EQ(h.phi(p + 300e6 / g3, 20, g3).slope, 0.0);
  }
  // F at the last stress: the smallest strain that reaches it, slope +inf (flat beyond)
  EXPECT_NEAR(h.f(300e6, 20, g3).value, 0.05 + 300e6 / g3, 1e-15);
  EXPECT_EQ(h.f(300e6, 20, g3).slope, inf);
  EXPECT_EQ(h.f(300e6 * (1 + 1e-9), 20, g3).value, inf);
  // a table of one point is perfectly plastic
  const Hardening one(table_spec(CurveSpec::Form::plastic, {table(0, 20, {0}, {240e6})}), E_T,
                      nu_c);
  EXPECT_DOUBLE_EQ(one.phi(0.01, 20, g3).value, 240e6);
  EXPECT_DOUBLE_EQ(one.max_stress(20), 240e6);
  EXPECT_EQ(one.table_end(), 0.0);
}

TEST(Hardening, PerfectAndSofteningEnds) {
  const double g3 = three_g(20);
  const Hardening perfect(analytic_spec(CurveSpec::Kind::perfect, constant(240e6)), E_T, nu_c);
  EXPECT_DOUBLE_EQ(perfect.max_stress(20), 240e6);
  // at the yield stress itself: the yield strain, with the slope of the flat part (+inf)
  EXPECT_DOUBLE_EQ(perfect.f(240e6, 20, g3).value, 240e6 / g3);
  EXPECT_EQ(perfect.f(240e6, 20, g3).slope, inf);
  EXPECT_EQ(perfect.f(240.1e6, 20, g3).value, inf);
  EXPECT_EQ(perfect.phi(240e6 / g3, 20, g3).slope, 0.0);  // to the right of the yield point
  // linear softening: H = 240e6 − 4e9·ε^p down to 0 at ε^p = 0.06, then 0
  const Hardening soft(analytic_spec(CurveSpec::Kind::linear, constant(240e6), constant(-4e9)), E_T,
                       nu_c);
  EXPECT_DOUBLE_EQ(soft.plastic(0.03, 20).value, 120e6);
  EXPECT_DOUBLE_EQ(soft.plastic(0.1, 20).value, 0.0);
  EXPECT_DOUBLE_EQ(soft.plastic(0.1, 20).slope, 0.0);
  EXPECT_DOUBLE_EQ(soft.phi(0.2, 20, g3).value, 0.0);
  EXPECT_DOUBLE_EQ(soft.max_stress(20), 240e6);
  EXPECT_EQ(soft.f(250e6, 20, g3).value, inf);
  // a softening table: F finds the rising part before the peak
  const Hardening table_soft(
      table_spec(CurveSpec::Form::plastic, {table(0, 20, {0, 0.01, 0.03}, {240e6, 300e6, 200e6})}),
      E_T, nu_c);
  EXPECT_DOUBLE_EQ(table_soft.max_stress(20), 300e6);
  EXPECT_NEAR(table_soft.f(270e6, 20, g3).value, 0.005 + 270e6 / g3, 1e-15);
  EXPECT_EQ(table_soft.f(300e6, 20, g3).slope, inf);  // falling to the right of the peak
  EXPECT_NEAR(table_soft.phi(0.02 + 250e6 / g3, 20, g3).value, 250e6, 1e-6);
  EXPECT_NEAR(table_soft.phi(0.02 + 250e6 / g3, 20, g3).slope, g3 * -5e9 / (g3 - 5e9), 1e-3);
}

TEST(Hardening, EvaluationsAreThreadSafe) {
  const auto curves = all_curves();
  const Hardening& h = curves[0].second;
  std::vector<double> x(4000);
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> u(0, 0.1);
  for (double& v : x) v = u(gen);
  std::vector<double> serial(x.size()), parallel(x.size());
  auto eval = [&](std::size_t i) {
    const double T = 20 + 480 * x[i] * 10;
    return h.phi(x[i], T, three_g(T)).value + h.f(200e6 * x[i] * 10, T, three_g(T)).value;
  };
  for (std::size_t i = 0; i < x.size(); ++i) serial[i] = eval(i);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (std::size_t i = t; i < x.size(); i += 4) parallel[i] = eval(i);
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(serial, parallel);
}

TEST(Hardening, WarnsOncePerMaterialOutsideTheTables) {
  const Hardening h(plastic_tables(), E_T, nu_c);
  Log log;
  log.quiet = true;
  h.warn_outside("steel", 20, 500, 0.04, log);  // inside; 0.04 < 0.05 but > 0.02 of T = 500
  ASSERT_EQ(log.warnings().size(), 1u);
  EXPECT_NE(log.warnings()[0].find("material 'steel'"), std::string::npos) << log.warnings()[0];
  EXPECT_NE(log.warnings()[0].find("beyond the last point"), std::string::npos);
  EXPECT_NE(log.warnings()[0].find("0.02 in the table at 500"), std::string::npos)
      << log.warnings()[0];
  h.warn_outside("iron", 20, 20, 0.04, log);  // the table at 20 reaches 0.05: fine
  h.warn_outside("steel", 0, 600, 0.01, log);
  ASSERT_EQ(log.warnings().size(), 2u);
  EXPECT_NE(log.warnings()[1].find("temperatures 0 .. 600"), std::string::npos)
      << log.warnings()[1];
  EXPECT_NE(log.warnings()[1].find("(20 .. 500)"), std::string::npos) << log.warnings()[1];
  h.warn_outside("steel", -10, 700, 0.3, log);  // once per material
  EXPECT_EQ(log.warnings().size(), 2u);
  h.warn_outside("copper", -10, 700, 0.3, log);  // another material warns again
  EXPECT_EQ(log.warnings().size(), 4u);
  // one table does not depend on temperature; analytic forms warn for their own tables
  Log log2;
  log2.quiet = true;
  Hardening(table_spec(CurveSpec::Form::plastic, {table(0, 20, {0, 0.1}, {2e8, 3e8})}), E_T, nu_c)
      .warn_outside("a", -100, 900, 0.05, log2);
  EXPECT_TRUE(log2.warnings().empty());
  Hardening(analytic_spec(CurveSpec::Kind::perfect,
                          over_temperature({20, 500}, {240e6, 150e6},
                                           "materials[0].plasticity.perfect.yield")),
            E_T, nu_c)
      .warn_outside("a", 20, 900, 5.0, log2);
  ASSERT_EQ(log2.warnings().size(), 1u);
  EXPECT_NE(log2.warnings()[0].find("'materials[0].plasticity.perfect.yield' (20 .. 500)"),
            std::string::npos)
      << log2.warnings()[0];
}

// ---------------------------------------------------------------------------------------------
// Bad curves

TEST(Hardening, NonIncreasingPlasticStrainNamesTableAndPoint) {
  // uniaxial, T = 500 (E = 1.7e11): ε^p of point 2 = 0.008 − 8e8/1.7e11 = 0.00329 is less
  // than point 1's 0.005 − 1.8e8/1.7e11 = 0.00394 (the stress rises faster than E)
  PlasticitySpec s = uniaxial_tables();
  s.curve.tables[1] = table(1, 500, {150e6 / 1.7e11, 0.005, 0.008}, {150e6, 180e6, 8e8});
  expect_error(s, {"case.yaml:11:40: 'materials[0].plasticity.curve.table[1]': point 2 (strain "
                   "0.008, stress 8e+08): its plastic strain ε − σ/E = ",
                   "does not increase from the previous point's", "E = 1.7e+11"});
  // a point left of the elastic line
  s.curve.tables[1] = table(1, 500, {150e6 / 1.7e11, 0.0005}, {150e6, 180e6});
  expect_error(s, {"case.yaml:11:30", "table[1]'", "point 1 (strain 5e-04, stress 1.8e+08)",
                   "on or left of the elastic line"});
  // plastic form
  s = plastic_tables();
  s.curve.tables[0] = table(0, 20, {0, 0.01, 0.01}, {240e6, 260e6, 270e6});
  expect_error(s, {"case.yaml:10:40", "table[0]'", "point 2 (strain 0.01, stress 2.7e+08)",
                   "the plastic strain must be strictly increasing, found 0.01 after 0.01"});
  // intensity form: ε̃^p = ε̃ − σ̃/3G
  s = intensity_tables();
  s.curve.tables[0] = table(0, 20, {240e6 / three_g(20), 0.0011}, {240e6, 300e6});
  expect_error(s, {"case.yaml:10:30", "table[0]'", "point 1", "ε̃ − σ̃/3G"});
}

TEST(Hardening, FirstPointOnTheElasticLine) {
  // 240e6/2.1e11 = 0.001142857: 0.00114286 is within 1e-3 relative, 0.001145 is not
  PlasticitySpec s =
      table_spec(CurveSpec::Form::uniaxial, {table(0, 20, {0.00114286, 0.01}, {240e6, 260e6})});
  EXPECT_NO_THROW(Hardening(s, E_T, nu_c));
  s.curve.tables[0].strain[0] = 0.001145;
  expect_error(s, {"case.yaml:10:20: 'materials[0].plasticity.curve.table[0]': point 0",
                   "the first point must be the yield point on the elastic line σ = E·ε",
                   "strain 0.00114286 (within 1e-3 relative)"});
  // intensity: on σ̃ = 3G·ε̃, with 3G at the table's temperature
  s = intensity_tables();
  s.curve.tables[1].strain[0] = 150e6 / three_g(20);
  expect_error(
      s, {"case.yaml:11:20", "table[1]'", "point 0", "σ̃ = 3G·ε̃", "at the table's temperature 500"});
  // plastic: the first strain is 0
  s = plastic_tables();
  s.curve.tables[1].strain[0] = 1e-4;
  expect_error(s, {"case.yaml:11:20", "table[1]'", "point 0 (strain 1e-04, stress 1.5e+08)",
                   "its strain must be 0"});
}

TEST(Hardening, SlopeNotAboveMinusThreeG) {
  // a fall of dσ̃/dε̃^p = −3G turns the curve back in ε̃^{e+p}
  const double g3 = three_g(20);
  PlasticitySpec s =
      table_spec(CurveSpec::Form::plastic,
                 {table(0, 20, {0, 0.001, 0.002}, {400e6, 450e6, 450e6 - 1.01 * g3 * 0.001})});
  expect_error(s, {"case.yaml:10:40", "table[0]'", "point 2", "falls too steeply",
                   "must be > -3G = -2.42308e+11"});
  s.curve.tables[0].stress[2] = 450e6 - 0.99 * g3 * 0.001;  // just above: allowed
  EXPECT_NO_THROW(Hardening(s, E_T, nu_c));
  // linear: the hardening modulus, at every temperature of E
  PropertyTable hard = constant(-0.95 * g3);
  hard.where = SourceLocation{"case.yaml", 7, 30, "materials[0].plasticity.linear.hardening"};
  expect_error(analytic_spec(CurveSpec::Kind::linear, constant(240e6), hard),
               {"case.yaml:7:30", "'materials[0].plasticity.linear.hardening'", "must be > -3G = -",
                "at temperature "});
  hard.value = {-0.95 * three_g(500)};
  EXPECT_NO_THROW(
      Hardening(analytic_spec(CurveSpec::Kind::linear, constant(240e6), hard), E_T, nu_c));
}

TEST(Hardening, OtherBadCurves) {
  PropertyTable y = constant(0);
  y.where = SourceLocation{"case.yaml", 7, 20, "materials[0].plasticity.perfect.yield"};
  expect_error(analytic_spec(CurveSpec::Kind::perfect, y),
               {"case.yaml:7:20", "the yield stress must be > 0, found 0"});
  y.value = {-1e8};
  expect_error(analytic_spec(CurveSpec::Kind::linear, y, constant(1e9)), {"found -1e+08"});
  expect_error(ramberg_osgood_spec(constant(240e6), 2e11, 0.002, 1.0), {"n must be > 1"});
  expect_error(ramberg_osgood_spec(constant(240e6), 2e11, 0.0, 5), {"alpha must be > 0"});
  // negative stresses, a first stress of 0
  PlasticitySpec s = plastic_tables();
  s.curve.tables[0].stress = {240e6, 260e6, -1};
  expect_error(s, {"case.yaml:10:40", "point 2", "stresses must be >= 0"});
  s.curve.tables[0].stress = {0, 260e6, 300e6};
  expect_error(s, {"case.yaml:10:20", "point 0", "the first point is the initial yield"});
  // table temperatures
  s = plastic_tables();
  s.curve.tables[1].temperature = 20;
  expect_error(s, {"case.yaml:11:11", "table[1]'", "strictly increasing, found 20 after 20"});
  // a spec built without locations still names the table
  s = plastic_tables();
  s.curve.tables[1].where = {};
  s.curve.tables[1].point_where.clear();
  s.curve.tables[1].strain[1] = 0;
  expect_error(s, {"'plasticity.curve.table[1]': point 1 (strain 0, stress 2e+08)"});
}

}  // namespace
}  // namespace hencky
