// Verification of thermo-plasticity through the whole solver: a bar whose axial displacement is
// held at both ends, heated uniformly beyond yield and cooled back (uniaxial stress: the lateral
// faces are free, rollers on y = 0 and z = 0 only remove the rigid motion), against hand
// calculations of the axial stress history.
//
// The state is homogeneous (the elements represent it exactly, distorted or not), so every
// number below is a hand formula and the only error is the iteration's stopping tolerance.
//
// Hand calculation (1D, uniaxial stress σ = σ_xx, total axial strain ε = 0 at every step):
//   σ = E(T)·(ε − ε^th(T) − ε^p) = −E(T)·(ε^th(T) + ε^p),  ε^th(T) = α(T)·T − α(T_ref)·T_ref
// (the secant α of the formulation (1.6); with E(T) this total form is what (1.9)'s ΔA·σ term
// gives step by step). Von Mises in uniaxial stress: σ̃ = |σ|, ε̃^p accumulates |dε^p|, and the
// yield condition is |σ| = H(ε̃^p, T) = σ_y(T) + h(T)·ε̃^p (isotropic hardening).
//  - heating, elastic: σ = −E ε^th, until E ε^th = σ_y;
//  - heating, plastic (compression): ε^p = −κ, ε̃^p = κ, E(ε^th − κ) = σ_y + hκ:
//      κ(T) = (E ε^th − σ_y)/(E + h),   σ = −(σ_y + hκ);
//  - cooling from the peak (κ₁ = κ(T_peak)), elastic: σ = E(κ₁ − ε^th) (it becomes tensile);
//  - cooling, reverse yield when σ reaches H(κ₁, T) = σ_y + hκ₁ (isotropic hardening: the
//    elastic range has grown to the same size in both directions), then ε^p = −κ₁ + κ₂,
//    ε̃^p = κ₁ + κ₂, E(κ₁ − κ₂ − ε^th) = σ_y + h(κ₁ + κ₂):
//      κ₂(T) = (E(κ₁ − ε^th) − σ_y − hκ₁)/(E + h),   σ = σ_y + h(κ₁ + κ₂).
// This holds while κ grows on heating and κ₂ on cooling (loading stays active); the hand
// calculation below checks that on the path it is evaluated on.
//
// What the solver does on reverse loading (docs/schemes.md, "Elastic unloading";
// src/material/plastic_point.cpp, StepCurve): below the largest intensity reached the curve is
// replaced by the elastic line σ̃ = 3G(ε̃^{e+p} − ε̃^p), up to the current yield stress
// H(ε̃^p, T) at the temperature of the end of the step. σ̃ does not know the sign of the stress,
// so the elastic range after a reversal is |σ| < H(ε̃^p, T): isotropic hardening, no Bauschinger
// effect. Reverse yield therefore starts at σ = +(σ_y + hκ₁) (kinematic hardening would have it
// at −(σ_y + hκ₁) + 2σ_y = σ_y − hκ₁), and the reverse flow keeps adding to ε̃^p. That is what
// the hand calculation above states and what the tests check. The schemes other than newton
// take Z from σ(t) for a point that flowed in the previous step; the first cooling step makes
// the projected strain increment negative, so it is elastic, the point stops flowing, and from
// the next step on Z comes from the elastic trial stress: the reverse yield is then found in the
// tensile direction like newton's radial return does. (A step that went from flowing in
// compression to tensile yield in one go would be taken elastic and corrected one step later;
// the steps here are a fraction of the 2ΔT_y a reversal needs.)
#include <gtest/gtest.h>

#include "verify_support.hpp"

namespace hencky::verify {
namespace {

/// A property as the case file's table over temperature: linear between the points, the end
/// values outside (a single point is a constant).
struct Table {
  std::vector<double> T, v;
  double operator()(double t) const {
    if (T.size() == 1 || t <= T.front()) return v.front();
    if (t >= T.back()) return v.back();
    std::size_t i = 1;
    while (T[i] < t) ++i;
    const double s = (t - T[i - 1]) / (T[i] - T[i - 1]);
    return (1 - s) * v[i - 1] + s * v[i];
  }
  std::string yaml() const {
    if (T.size() == 1) return num(v.front());
    std::string t = "{temperature: [", w = "], value: [";
    for (std::size_t i = 0; i < T.size(); ++i) {
      t += i ? ", " : "";
      t += num(T[i]);
      w += i ? ", " : "";
      w += num(v[i]);
    }
    return t + w + "]}";
  }
};

Table constant(double v) {
  return {{0.0}, {v}};
}

struct BarMaterial {
  Table E, nu, alpha, yield, hardening;
  bool perfect = false;  ///< written as perfect: {yield} (hardening must be 0)
  double T_ref = 20;

  double eps_th(double T) const { return alpha(T) * T - alpha(T_ref) * T_ref; }

  std::string yaml() const {
    const std::string curve = perfect ? fmt::format("perfect: {{yield: {}}}", yield.yaml())
                                      : fmt::format("linear: {{yield: {}, hardening: {}}}",
                                                    yield.yaml(), hardening.yaml());
    return fmt::format("  - {{E: {}, nu: {}, alpha: {}, plasticity: {{{}}}}}\n", E.yaml(),
                       nu.yaml(), alpha.yaml(), curve);
  }
};

/// The hand calculation's state at one point of the path.
struct BarState {
  double sigma = 0;   ///< axial stress
  double eps_p = 0;   ///< axial plastic strain (signed)
  double eps_pq = 0;  ///< equivalent plastic strain ε̃^p
};

/// The path: T_ref → T_peak for 0 ≤ t ≤ 1, back to T_ref for 1 ≤ t ≤ 2, linearly.
struct BarPath {
  BarMaterial m;
  double T_peak = 0;

  double temperature(double t) const { return m.T_ref + (T_peak - m.T_ref) * (t <= 1 ? t : 2 - t); }
  /// κ on heating (0 while elastic).
  double kappa(double T) const {
    const double E = m.E(T), h = m.hardening(T);
    return std::max(0.0, (E * m.eps_th(T) - m.yield(T)) / (E + h));
  }
  BarState at(double t) const {
    const double T = temperature(t), E = m.E(T), sy = m.yield(T), h = m.hardening(T);
    BarState s;
    if (t <= 1) {
      const double k = kappa(T);
      s.sigma = k > 0 ? -(sy + h * k) : -E * m.eps_th(T);
      s.eps_p = -k;
      s.eps_pq = k;
      return s;
    }
    const double k1 = kappa(T_peak);
    const double k2 = std::max(0.0, (E * (k1 - m.eps_th(T)) - sy - h * k1) / (E + h));
    s.sigma = E * (k1 - k2 - m.eps_th(T));
    s.eps_p = -k1 + k2;
    s.eps_pq = k1 + k2;
    return s;
  }
  /// The hand calculation's own assumptions along the path (sampled finely): κ never
  /// decreases on heating, κ₂ never on cooling, and the elastic stretches stay inside the yield
  /// surface (no compressive re-yield on cooling).
  void check_assumptions() const {
    double k_prev = 0, k2_prev = 0;
    for (int i = 0; i <= 2000; ++i) {
      const double t = i / 1000.0, T = temperature(t);
      const BarState s = at(t);
      const double H = m.yield(T) + m.hardening(T) * s.eps_pq;
      ASSERT_LE(std::abs(s.sigma), H * (1 + 1e-12)) << "hand calculation off the curve, t " << t;
      if (t <= 1) {
        ASSERT_GE(s.eps_pq, k_prev) << "κ decreases on heating at t " << t;
        k_prev = s.eps_pq;
      } else {
        const double k2 = s.eps_pq - kappa(T_peak);
        ASSERT_GE(k2, k2_prev) << "κ₂ decreases on cooling at t " << t;
        k2_prev = k2;
      }
    }
  }
};

/// A bar [0, L] x [0, w] x [0, w] of n hexahedra along x (8- or 20-node, Gmsh MSH 2.2), the
/// inner cross-sections tilted (their nodes moved along x by up to `skew` of the element
/// length, differently at each corner) so that the elements are not parallelepipeds.
/// Regions: body; faces x0 x1 y0 y1 z0 z1.
std::string bar_msh(int n, bool quadratic, double L, double w, double skew) {
  MshBuilder b;
  auto id = [&](int i, int j, int k) { return 1 + i + (n + 1) * (j + 2 * k); };
  const double dx = L / n;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i <= n; ++i) {
        const double shift =
            (i > 0 && i < n) ? skew * dx * ((j + 2 * k) % 3 - 1) * (i % 2 ? 1 : -1) : 0.0;
        b.x.emplace_back(i * dx + shift, j * w, k * w);
      }
  for (int i = 0; i < n; ++i) {
    const std::array<int, 8> c{id(i, 0, 0), id(i + 1, 0, 0), id(i + 1, 1, 0), id(i, 1, 0),
                               id(i, 0, 1), id(i + 1, 0, 1), id(i + 1, 1, 1), id(i, 1, 1)};
    b.hex(c, quadratic, 1);
    auto quad = [&](int tag, int a, int bb, int cc, int d) {
      b.quad(c[a], c[bb], c[cc], c[d], quadratic, tag);
    };
    if (i == 0) quad(11, 0, 3, 7, 4);
    if (i == n - 1) quad(12, 1, 2, 6, 5);
    quad(13, 0, 1, 5, 4);
    quad(14, 3, 2, 6, 7);
    quad(15, 0, 1, 2, 3);
    quad(16, 4, 5, 6, 7);
  }
  return b.text(box_region_names());
}

constexpr double bar_L = 0.4, bar_w = 0.05;

std::string bar_case(const BarPath& path, const std::string& scheme, double omega, int steps,
                     const std::string& form, int max_iterations) {
  return fmt::format(
      "mesh: {{file: bar.msh}}\n"
      "materials:\n{}"
      "temperature: {{reference: {}, field: \"{} + {}*(t <= 1 ? t : 2 - t)\"}}\n"
      "boundary:\n"
      "  - {{region: x0, displacement: {{x: 0}}}}\n"
      "  - {{region: x1, displacement: {{x: 0}}}}\n"
      "  - {{region: y0, displacement: {{y: 0}}}}\n"
      "  - {{region: z0, displacement: {{z: 0}}}}\n"
      "solver: {{scheme: {}, curve_form: {}, relaxation: {}, steps: {}, end: 2, tolerance: 1e-10, "
      "max_iterations: {}, cutback: 2}}\n",
      path.m.yaml(), num(path.m.T_ref), num(path.m.T_ref), num(path.T_peak - path.m.T_ref), scheme,
      form, num(omega), steps, max_iterations);
}

struct BarErrors {
  double stress = 0, eps_p = 0, eps_pq = 0, lateral = 0;  ///< largest over the path
};

/// Compares every converged step with the hand calculation: the axial stress and the plastic
/// strains at every integration point, the other stresses zero, and the lateral displacement
/// of the free faces, u_y(y = w) = w·ε_yy with ε_yy = ε^th − ν σ/E − ε^p/2 (which checks the
/// thermal strain and the elastic strain at E(T)).
/// Tolerances: the state is homogeneous and represented exactly, so the error is that of the
/// iteration stopped at a relative 1e-10 (slower for the relaxed initial-strain schemes, whose
/// error is the last correction divided by 1 − contraction, contraction ≤ 0.7 here): 1e-7 σ_y on
/// stresses and 1e-9 on strains leave two orders of magnitude above that and catch any error
/// in the formulation (a wrong E, α, σ_y(T) or a missed ΔA·σ term is ≥ 1e-4 relative).
BarErrors check_bar(const SteppedRun& r, const BarPath& path) {
  BarErrors err;
  const Model& m = r.model();
  const Mesh& mesh = m.mesh();
  const double sy_scale = path.m.yield(path.m.T_ref);
  for (std::size_t k = 0; k < r.all.states.size(); ++k) {
    const double t = r.all.reports[k].time, T = path.temperature(t);
    const BarState hand = path.at(t);
    const State& s = r.all.states[k];
    for (std::size_t p = 0; p < s.stress.size(); ++p) {
      EXPECT_NEAR(s.temperature[p], T, 1e-9 * std::abs(T)) << "t " << t;
      err.stress = std::max(err.stress, std::abs(s.stress[p][0] - hand.sigma) / sy_scale);
      for (int c = 1; c < 6; ++c)
        err.stress = std::max(err.stress, std::abs(s.stress[p][c]) / sy_scale);
      err.eps_p = std::max(err.eps_p, std::abs(s.plastic_strain[p][0] - hand.eps_p));
      err.eps_p = std::max(err.eps_p, std::abs(s.plastic_strain[p][1] + 0.5 * hand.eps_p));
      err.eps_pq = std::max(err.eps_pq, std::abs(s.eps_p_eq[p] - hand.eps_pq));
      EXPECT_NEAR(s.stress[p][0], hand.sigma, 1e-7 * sy_scale) << "t " << t << " T " << T;
      EXPECT_NEAR(s.eps_p_eq[p], hand.eps_pq, 1e-9) << "t " << t << " T " << T;
      EXPECT_NEAR(s.plastic_strain[p][0], hand.eps_p, 1e-9) << "t " << t << " T " << T;
    }
    const double eyy =
        path.m.eps_th(T) - path.m.nu(T) * hand.sigma / path.m.E(T) - 0.5 * hand.eps_p;
    for (int i = 0; i < mesh.n_nodes(); ++i) {
      if (std::abs(mesh.x[i].y() - bar_w) > 1e-12) continue;
      const double e = std::abs(s.u[3 * i + 1] - bar_w * eyy) / bar_w;
      err.lateral = std::max(err.lateral, e);
      EXPECT_NEAR(s.u[3 * i + 1], bar_w * eyy, 1e-9 * bar_w) << "t " << t << " node " << i;
    }
  }
  EXPECT_LT(err.stress, 1e-7);
  return err;
}

/// What a scheme does on a path: converges, stops (for a reason the test explains; the steps
/// it converged are checked all the same), or is refused when the case is read (a scheme on
/// the strain form of a curve that has none above its yield stress).
enum class Outcome { converges, stops, refused };

struct SchemeRun {
  std::string scheme, form = "stress";
  double omega = 1.0;
  Outcome outcome = Outcome::converges;
  int max_iterations = 200;
};

/// Runs the path with each scheme, reports, checks the convergence expectation and (when it
/// converged, and on the steps it did converge otherwise) the hand calculation.
void run_schemes(const std::string& tag, const BarPath& path, const std::vector<SchemeRun>& runs,
                 int steps, bool quadratic) {
  path.check_assumptions();
  for (const auto& [scheme, form, omega, outcome, max_iterations] : runs) {
    SCOPED_TRACE(tag + ": " + scheme + (form == "strain" ? " (strain form)" : ""));
    TempDir dir("bar-" + scheme);
    write_file(dir / "bar.msh", bar_msh(4, quadratic, bar_L, bar_w, 0.2));
    if (outcome == Outcome::refused) {
      try {
        run_stepped(dir.path(), bar_case(path, scheme, omega, steps, form, max_iterations));
        ADD_FAILURE() << "the case was not refused";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("strain form"), std::string::npos) << e.what();
        report(fmt::format("{} {:<26} refused: {}", tag, scheme, e.what()));
      }
      continue;
    }
    auto r = run_stepped(dir.path(), bar_case(path, scheme, omega, steps, form, max_iterations));
    const BarErrors e = check_bar(*r, path);
    report(fmt::format(
        "{} {:<26} {} {:2d}/{} steps, {:4d} iterations, {:3d} factorizations, {:.2f} s; "
        "max err: sigma {:.1e} sy, eps_p {:.1e}, eps_p_eq {:.1e}, u_y {:.1e}{}",
        tag, scheme + (form == "strain" ? " (strain)" : ""),
        r->result.status == AnalysisStatus::converged ? "converged" : "STOPPED  ",
        r->all.reports.size(), steps, r->result.iterations, r->result.factorizations, r->seconds,
        e.stress, e.eps_p, e.eps_pq, e.lateral,
        r->result.failure.empty() ? "" : ": " + r->result.failure));
    EXPECT_EQ(r->result.status == AnalysisStatus::converged, outcome == Outcome::converges)
        << r->result.failure;
  }
}

// ------------------------------------------------------------------------------------------
// a) Constant properties: E = 200 GPa, α = 1.2e-5/K, σ_y = 240 MPa: ΔT_y = σ_y/(Eα) = 100 K.

BarMaterial constant_bar(double hardening) {
  BarMaterial m;
  m.E = constant(2e11);
  m.nu = constant(0.3);
  m.alpha = constant(1.2e-5);
  m.yield = constant(2.4e8);
  m.hardening = constant(hardening);
  m.perfect = hardening == 0;
  return m;
}

// Which schemes follow the constant-property cycles, and why the others do not:
// - newton, variable-stiffness, initial-stress, initial-stress-stiffness (and the initial-strain
//   schemes with hardening) converge and reproduce the hand calculation to round-off.
// - initial-strain, initial-strain-stiffness (perfect plasticity): they need F = ε(σ), which
//   does not exist at σ̃ = σ_y of a flat curve (docs/schemes.md, Limits); the case is refused
//   when it is read, with a message that names the schemes that can run it.
// The -stiffness schemes owe this to two decisions in src/solve/scheme_law.cpp, which this test
// was written to expose (before them their outcome here depended on round-off):
//   · the start slope tan β*_0 of a point that flowed is the curve's loading slope even when
//     σ̃(t) lies an ulp below the yield stress H(ε̃^p) (before: 3G for an ulp below, the curve's
//     slope otherwise, point by point at random; the heating steps then crawled with a matrix
//     that fit neither);
//   · at the first cooling step the points unload elastically (stiffness 3G along Z). With the
//     loading slope kept, the fixed-matrix iteration multiplies the error at such a point by
//     1 − 3G/tan β*_0 ≈ −58 (h = 0.02E) and diverges. A flowing point whose first iterates
//     show it unloading gets the start slope 3G (one more factorization in that step), and
//     initial-strain-stiffness drops the initial strain it had gathered for the loading matrix.
const std::vector<SchemeRun> perfect_runs = {
    {"newton"},
    {"variable-stiffness"},
    {"initial-stress"},
    {"initial-stress-stiffness"},
    {"initial-strain", "stress", 1.0, Outcome::refused},
    {"initial-strain-stiffness", "stress", 1.0, Outcome::refused},
};
// With hardening h = 0.02 E all six schemes are tried. The initial-strain schemes contract by
// 1 − ω(1 + E/h) at first yield in uniaxial stress (test_verify_plastic.cpp; the matrix of the
// -stiffness variant is elastic there too, the point was elastic at t): ω must stay below
// 2h/(E + h) = 0.039; ω = 0.03 (contraction −0.53).
const std::vector<SchemeRun> hardening_runs = {
    {"newton"},
    {"variable-stiffness"},
    {"initial-strain", "stress", 0.03},
    {"initial-strain-stiffness", "stress", 0.03},
    {"initial-stress"},
    {"initial-stress-stiffness"},
};

TEST(VerifyPlasticThermal, ConstrainedBarPerfectPlasticity) {
  const double dTy = 100;
  for (double factor : {1.5, 3.0}) {
    BarPath path{constant_bar(0.0), 20 + factor * dTy};
    // Explicit numbers of the hand calculation: after heating σ = −σ_y; after cooling
    // σ = Eα(ΔT − ΔT_y) = (factor − 1)σ_y when that is below σ_y (ΔT < 2ΔT_y), else the bar
    // yields again in tension and ends at +σ_y, with ε̃^p = (ΔT − ΔT_y)α + (ΔT − 2ΔT_y)α.
    const double sy = 2.4e8, a = 1.2e-5, dT = factor * dTy;
    EXPECT_DOUBLE_EQ(path.at(1).sigma, -sy);
    EXPECT_NEAR(path.at(2).sigma, std::min(factor - 1, 1.0) * sy, 1e-9 * sy);
    EXPECT_NEAR(path.at(2).eps_pq, (dT - dTy) * a + std::max(0.0, dT - 2 * dTy) * a, 1e-15);
    // 40 steps: 0.075 and 0.15 ΔT_y per step
    run_schemes(fmt::format("bar perfect dT {:.1f} dTy", factor), path, perfect_runs, 40, false);
  }
}

TEST(VerifyPlasticThermal, ConstrainedBarLinearIsotropicHardening) {
  const double dTy = 100, E = 2e11, h = 0.02 * E, sy = 2.4e8, a = 1.2e-5;
  for (double factor : {1.5, 3.0}) {
    BarPath path{constant_bar(h), 20 + factor * dTy};
    // Explicit numbers: κ₁ = (EαΔT − σ_y)/(E + h), σ after heating −(σ_y + hκ₁). Cooling to T_ref
    // elastically gives Eκ₁, which exceeds the grown yield stress σ_y + hκ₁ when
    // ΔT > 2ΔT_y·E/(E − h) (= 204 K): not for 1.5 ΔT_y (σ = Eκ₁ = 0.490 σ_y), yes for
    // 3 ΔT_y: κ₂ = (Eκ₁ − σ_y − hκ₁)/(E + h), σ = σ_y + h(κ₁ + κ₂) = 1.0573 σ_y
    // (above σ_y: the isotropic hardening of the heating raised the tensile yield too).
    const double k1 = (E * a * factor * dTy - sy) / (E + h);
    EXPECT_NEAR(path.at(1).sigma, -(sy + h * k1), 1e-9 * sy);
    if (factor < 2) {
      EXPECT_NEAR(path.at(2).sigma, E * k1, 1e-9 * sy);
      EXPECT_NEAR(path.at(2).sigma, 0.490196 * sy, 1e-6 * sy);
    } else {
      const double k2 = (E * k1 - sy - h * k1) / (E + h);
      EXPECT_NEAR(path.at(2).sigma, sy + h * (k1 + k2), 1e-9 * sy);
      EXPECT_NEAR(path.at(2).sigma, 1.057286 * sy, 1e-6 * sy);
      EXPECT_NEAR(path.at(2).eps_pq, k1 + k2, 1e-15);
    }
    run_schemes(fmt::format("bar linear dT {:.1f} dTy", factor), path, hardening_runs, 40, false);
  }
}

// ------------------------------------------------------------------------------------------
// b) Temperature-dependent E(T), α(T), σ_y(T) and h(T) (three-point tables), heated from 20 to
// 500 °C and cooled back: the bar yields in compression at 134 °C, flows while E and σ_y fall,
// unloads when the cooling starts, and yields in tension on the way down (at 340 °C with
// hardening, 361 °C without) while the yield stress rises again; it ends at +σ_y(20 °C) = 300 MPa
// (perfect) or 357 MPa (hardening). On 20-node hexahedra.

BarMaterial table_bar(bool perfect) {
  BarMaterial m;
  m.E = {{20, 300, 600}, {2.0e11, 1.85e11, 1.5e11}};
  m.nu = constant(0.3);
  m.alpha = {{20, 300, 600}, {1.2e-5, 1.3e-5, 1.45e-5}};
  m.yield = {{20, 300, 600}, {3.0e8, 2.4e8, 1.2e8}};
  m.hardening = perfect ? constant(0.0) : Table{{20, 300, 600}, {6e9, 5e9, 3e9}};
  m.perfect = perfect;
  return m;
}

TEST(VerifyPlasticThermal, TemperatureDependentYieldLinearHardeningEveryScheme) {
  const BarPath path{table_bar(false), 500};
  // Which schemes converge, and why the others do not:
  // - variable-stiffness (both forms): the secant of (2.33), (Φ(ε̃(t) + Δε̃) − σ̃(t))/Δε̃, is
  //   taken from the stress at t to the curve at T(t+Δt). While the bar is heated in the plastic
  //   range the yield stress falls faster than the hardening raises it, Φ(ε̃(t) + Δε̃) < σ̃(t),
  //   and the secant is negative. D̃(β*) was then indefinite and the Cholesky factorization
  //   failed at the first step that starts plastic (t = 0.3); the matrix now takes the curve's
  //   slope there (the stress form's iterate does not depend on it; a strain-form point with a
  //   negative secant takes the stress form), and both forms give the closed form.
  // - initial-strain and initial-strain-stiffness: ω must stay below 2h/(E + h) at first yield
  //   (in compression at 134 °C: 0.056; in tension on cooling at 340 °C: 0.050); ω = 0.03.
  //   initial-strain-stiffness then converges, but slowly: in a step that starts plastic its
  //   matrix already has the curve's slope, and what is left to correct, the shift of the curve
  //   with the temperature, goes away only by the factor 1 − ω per iteration (≈ 300 iterations
  //   per step here); initial-strain with its elastic matrix contracts by 1 − ω(1 + E/h) ≈ 0.
  // - newton, initial-stress, initial-stress-stiffness converge in a few iterations.
  const std::vector<SchemeRun> runs = {
      {"newton"},
      {"variable-stiffness", "stress"},
      {"variable-stiffness", "strain"},
      {"initial-strain", "stress", 0.03},
      {"initial-strain-stiffness", "stress", 0.03, Outcome::converges, 1000},
      {"initial-stress"},
      {"initial-stress-stiffness"},
  };
  run_schemes("bar E(T) sy(T) h(T)", path, runs, 40, true);
}

TEST(VerifyPlasticThermal, TemperatureDependentYieldPerfectPlasticityEveryScheme) {
  const BarPath path{table_bar(true), 500};
  // Plastic flow at σ = −σ_y(T) while heating, then (after the reverse yield at 361 °C)
  // σ = +σ_y(T) while cooling, ending at +σ_y(20 °C). The initial-strain schemes cannot use F at
  // σ̃ = σ_y (no hardening); variable-stiffness meets the negative secant explained above.
  const std::vector<SchemeRun> runs = {
      {"newton"},
      {"variable-stiffness", "stress"},
      {"initial-stress"},
      {"initial-stress-stiffness"},
      {"initial-strain", "stress", 1.0, Outcome::refused},
      {"initial-strain-stiffness", "stress", 1.0, Outcome::refused},
  };
  run_schemes("bar E(T) perfect sy(T)", path, runs, 40, true);
  // the explicit end values of the hand calculation: −σ_y(500 °C) at the peak, +σ_y(20 °C) at
  // the end
  EXPECT_NEAR(path.at(1).sigma, -path.m.yield(500), 1e-9 * path.m.yield(500));
  EXPECT_NEAR(path.at(2).sigma, path.m.yield(20), 1e-9 * path.m.yield(20));
}

}  // namespace
}  // namespace hencky::verify
