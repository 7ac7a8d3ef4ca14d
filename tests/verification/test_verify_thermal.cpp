// Verification of thermo-elasticity: heated cubes (constrained and free), thermal stresses in a
// long hollow cylinder (plane strain, logarithmic temperature) with observed convergence, and
// temperature-dependent E and α over several steps (path independence of the elastic answer,
// which rests on the ΔA·σ term of (1.9)), with and without the error correction.
#include <gtest/gtest.h>

#include "verify_support.hpp"

using namespace hencky;
using namespace hencky::verify;

namespace {

constexpr double E = 2.0e11, nu = 0.3, alpha = 1.2e-5;

std::string material_yaml() {
  return fmt::format("materials:\n  - name: steel\n    E: {}\n    nu: {}\n    alpha: {}\n", num(E), num(nu),
                     num(alpha));
}

const char* const rollers =
    "  - region: x0\n    displacement: {x: 0}\n  - region: x1\n    displacement: {x: 0}\n"
    "  - region: y0\n    displacement: {y: 0}\n  - region: y1\n    displacement: {y: 0}\n"
    "  - region: z0\n    displacement: {z: 0}\n  - region: z1\n    displacement: {z: 0}\n";

const char* const three_two_one =
    "  - region: p000\n    displacement: {x: 0, y: 0, z: 0}\n"
    "  - region: p100\n    displacement: {y: 0, z: 0}\n"
    "  - region: p010\n    displacement: {z: 0}\n";

struct CubeMesh {
  std::string label, file, text;
  int order;
};
std::vector<CubeMesh> cube_meshes() {
  return {{"hex20", "cube.msh", cube_msh(3, GridCells::hex20, 0.25), 0},
          {"tet10", "box.geo", box_geo(1, 1, 1, 0.45), 2},
          {"wedge6", "cube.msh", cube_msh(3, GridCells::wedge6, 0.25), 0}};
}

std::string cube_case(const CubeMesh& m, const std::string& boundary) {
  std::string s = fmt::format("title: heated cube {}\nmesh:\n  file: {}\n", m.label, m.file);
  if (m.order > 0) s += fmt::format("  order: {}\n", m.order);
  return s + material_yaml() + "temperature: {reference: 20, field: 120}\nboundary:\n" + boundary;
}

// Every face held in its normal direction: ε = 0, so σ_ii = −E α ΔT / (1 − 2ν), no shear.
TEST(VerifyHeatedCube, FullyConstrainedStressIsHydrostatic) {
  const double dT = 100, s_exact = -E * alpha * dT / (1 - 2 * nu);
  for (const CubeMesh& m : cube_meshes()) {
    TempDir dir("heated-constrained-" + m.label);
    write_file(dir / m.file, m.text);
    auto r = run_case(dir.path(), cube_case(m, rollers));
    double err = 0, umax = 0;
    for (const Voigt& s : r->state().stress) {
      Voigt e = s;
      e.head<3>().array() -= s_exact;
      err = std::max(err, e.lpNorm<Eigen::Infinity>() / std::abs(s_exact));
    }
    for (double u : r->state().u) umax = std::max(umax, std::abs(u));
    report(fmt::format("heated cube constrained {:<6}: sigma_exact {:.6e}  max|dsigma|/|sigma| {:.2e}  "
                       "max|u|/(alpha dT L) {:.2e}",
                       m.label, s_exact, err, umax / (alpha * dT)));
    EXPECT_LT(err, 1e-10) << m.label;
    EXPECT_LT(umax / (alpha * dT), 1e-10) << m.label;
  }
}

// Held by three points only: free thermal expansion u = α ΔT x, no stress.
TEST(VerifyHeatedCube, FreeExpansionIsStressFree) {
  const double dT = 100, scale = E * alpha * dT / (1 - 2 * nu);
  for (const CubeMesh& m : cube_meshes()) {
    TempDir dir("heated-free-" + m.label);
    write_file(dir / m.file, m.text);
    auto r = run_case(dir.path(), cube_case(m, three_two_one));
    double serr = 0, uerr = 0;
    for (const Voigt& s : r->state().stress) serr = std::max(serr, s.lpNorm<Eigen::Infinity>() / scale);
    const Mesh& mesh = r->model().mesh();
    for (int n = 0; n < mesh.n_nodes(); ++n)
      uerr = std::max(uerr, (r->u(n) - alpha * dT * mesh.x[n]).lpNorm<Eigen::Infinity>() / (alpha * dT));
    report(fmt::format("heated cube free        {:<6}: max|sigma|/(E alpha dT/(1-2nu)) {:.2e}  "
                       "max|u - alpha dT x|/(alpha dT L) {:.2e}",
                       m.label, serr, uerr));
    EXPECT_LT(serr, 1e-10) << m.label;
    EXPECT_LT(uerr, 1e-10) << m.label;
  }
}

// Free expansion superposed on a uniform tension s along x (rollers on x0, y0, z0, traction on
// x1): σ = diag(s, 0, 0) and u = (s/E + α ΔT) x e_x + (−ν s/E + α ΔT)(y e_y + z e_z), exactly.
TEST(VerifyHeatedCube, FreeExpansionUnderTension) {
  const double dT = 100, s = 50e6;
  for (const CubeMesh& m : cube_meshes()) {
    TempDir dir("heated-tension-" + m.label);
    write_file(dir / m.file, m.text);
    auto r = run_case(dir.path(), cube_case(m, fmt::format("  - region: x0\n    displacement: {{x: 0}}\n"
                                                           "  - region: y0\n    displacement: {{y: 0}}\n"
                                                           "  - region: z0\n    displacement: {{z: 0}}\n"
                                                           "  - region: x1\n    traction: [{}, 0, 0]\n",
                                                           num(s))));
    Voigt expect;
    expect << s, 0, 0, 0, 0, 0;
    double serr = 0, uerr = 0;
    for (const Voigt& q : r->state().stress) serr = std::max(serr, (q - expect).lpNorm<Eigen::Infinity>() / s);
    const Vec3 g(s / E + alpha * dT, -nu * s / E + alpha * dT, -nu * s / E + alpha * dT);
    const Mesh& mesh = r->model().mesh();
    for (int n = 0; n < mesh.n_nodes(); ++n)
      uerr = std::max(uerr, (r->u(n) - g.cwiseProduct(mesh.x[n])).lpNorm<Eigen::Infinity>() / g.maxCoeff());
    report(fmt::format("heated cube + tension   {:<6}: max|dsigma|/s {:.2e}  max|du|/|u| {:.2e}", m.label,
                       serr, uerr));
    EXPECT_LT(serr, 1e-8) << m.label;
    EXPECT_LT(uerr, 1e-10) << m.label;
  }
}

// ------------------------------------------------------------------------------------------
// Long hollow cylinder a <= r <= b, T = T_a ln(b/r) / ln(b/a) (T_ref = 0), plane strain
// (ε_z = 0), free surfaces. Timoshenko & Goodier §152 (plane-strain form), with
// I(r) = ∫_a^r T ρ dρ:
//   u_r = (1+ν) α / (1−ν) · [ I(r)/r + ((1−2ν) r² + a²) I(b) / ((b² − a²) r) ]
//   σ_r = α E / ((1−ν) r²) · [ (r² − a²)/(b² − a²) I(b) − I(r) ]
//   σ_θ = α E / ((1−ν) r²) · [ (r² + a²)/(b² − a²) I(b) + I(r) − T r² ]
//   σ_z = ν (σ_r + σ_θ) − α E T
struct ThermalCylinder {
  double a = 1.0, b = 2.0, Ta = 100.0;
  double T(double r) const { return Ta * std::log(b / r) / std::log(b / a); }
  double I(double r) const {  // ∫ ρ ln(b/ρ) dρ = ρ²/2 ln(b/ρ) + ρ²/4
    auto F = [&](double p) { return p * p / 2 * std::log(b / p) + p * p / 4; };
    return Ta / std::log(b / a) * (F(r) - F(a));
  }
  Vec3 u(const Vec3& x) const {
    const double r = std::hypot(x.x(), x.y());
    const double ur = (1 + nu) * alpha / (1 - nu) *
                      (I(r) / r + ((1 - 2 * nu) * r * r + a * a) * I(b) / ((b * b - a * a) * r));
    return {ur * x.x() / r, ur * x.y() / r, 0};
  }
  Voigt stress(const Vec3& x) const {
    const double r2 = x.x() * x.x() + x.y() * x.y(), r = std::sqrt(r2), k = alpha * E / ((1 - nu) * r2);
    const double d = b * b - a * a;
    const double sr = k * ((r2 - a * a) / d * I(b) - I(r));
    const double st = k * ((r2 + a * a) / d * I(b) + I(r) - T(r) * r2);
    const double sz = nu * (sr + st) - alpha * E * T(r);
    const double c2 = x.x() * x.x() / r2, s2 = x.y() * x.y() / r2, cs = x.x() * x.y() / r2;
    Voigt s;
    s << sr * c2 + st * s2, sr * s2 + st * c2, sz, 0, 0, (sr - st) * cs;
    return s;
  }
};

/// from_heat: the temperature from a steady heat analysis between T_a on the bore and 0 on the
/// outer surface (whose exact solution is the same logarithm) instead of the expression.
void thermal_cylinder(const std::string& label, const std::string& cells, int order,
                      double min_rate, double min_stress_rate, bool from_heat = false) {
  const ThermalCylinder C;
  // The closed form must satisfy its own boundary conditions σ_r(a) = σ_r(b) = 0.
  ASSERT_NEAR(C.stress(Vec3(C.a, 0, 0))[0], 0.0, 1e-6);
  ASSERT_NEAR(C.stress(Vec3(C.b, 0, 0))[0], 0.0, 1e-6);
  std::vector<double> h, eu, es;
  for (int nr : {2, 4, 8}) {
    TempDir dir(fmt::format("thermal-cylinder-{}-{}", label, nr));
    write_file(dir / "ring.geo", quarter_ring_geo(C.a, C.b, (C.b - C.a) / nr, nr, 2 * nr, cells));
    const std::string temperature =
        from_heat ? fmt::format(
                        "    conductivity: 45\ntemperature: {{reference: 0, from: heat}}\n"
                        "heat:\n  boundary:\n    - {{region: inner, temperature: {}}}\n"
                        "    - {{region: outer, temperature: 0}}\n",
                        num(C.Ta))
                  : fmt::format(
                        "temperature:\n  reference: 0\n  field: "
                        "\"{}*log({}/sqrt(x^2 + y^2))/log({}/{})\"\n",
                        num(C.Ta), num(C.b), num(C.b), num(C.a));
    auto r =
        run_case(dir.path(),
                 fmt::format("title: thermal cylinder\nmesh:\n  file: ring.geo\n  order: {}\n{}{}"
                             "boundary:\n"
                             "  - region: xsym\n    displacement: {{x: 0}}\n"
                             "  - region: ysym\n    displacement: {{y: 0}}\n"
                             "  - region: bottom\n    displacement: {{z: 0}}\n"
                             "  - region: top\n    displacement: {{z: 0}}\n",
                             order, material_yaml(), temperature));
    const L2Norms n = l2_displacement_error(r->model(), r->state(), [&](const Vec3& x) { return C.u(x); });
    const double se = l2_stress_error(r->model(), r->state(), [&](const Vec3& x) { return C.stress(x); });
    report(fmt::format("thermal cylinder {:<5} nr {} cells {:4d}  L2(u) rel {:.3e}  L2(sigma) rel {:.3e}",
                       label, nr, n.cells, n.relative(), se));
    h.push_back((C.b - C.a) / nr);
    eu.push_back(n.relative());
    es.push_back(se);
  }
  const double ru = observed_rate(h, eu), rs = observed_rate(h, es);
  const double ru_last = std::log2(eu[1] / eu[2]), rs_last = std::log2(es[1] / es[2]);
  report(fmt::format("thermal cylinder {:<5} observed rates: L2(u) {:.3f} (last pair {:.3f})  "
                     "L2(sigma) {:.3f} (last pair {:.3f})",
                     label, ru, ru_last, rs, rs_last));
  ::testing::Test::RecordProperty("u_rate", fmt::format("{:.3f}", ru));
  ::testing::Test::RecordProperty("stress_rate", fmt::format("{:.3f}", rs));
  for (std::size_t i = 1; i < eu.size(); ++i) {
    EXPECT_LT(eu[i], eu[i - 1]);
    EXPECT_LT(es[i], es[i - 1]);
  }
  EXPECT_GT(ru, min_rate);
  EXPECT_GT(ru_last, min_rate);
  EXPECT_GT(rs, min_stress_rate);
  EXPECT_GT(rs_last, min_stress_rate);
}

TEST(VerifyThermalCylinder, Hex20PlaneStrain) { thermal_cylinder("hex20", "hex", 2, 2.7, 1.6); }
TEST(VerifyThermalCylinder, Hex8PlaneStrain) { thermal_cylinder("hex8", "hex", 1, 1.8, 0.8); }
TEST(VerifyThermalCylinder, Tet10PlaneStrain) { thermal_cylinder("tet10", "tet", 2, 2.7, 1.6); }
// The same with the temperature of a steady heat analysis: T_h's own error (third order in L2
// for quadratic cells) adds to the displacement's, with the same orders.
TEST(VerifyThermalCylinder, Hex20FromSteadyHeat) {
  thermal_cylinder("hex20 heat", "hex", 2, 2.7, 1.6, true);
}
TEST(VerifyThermalCylinder, Tet10FromSteadyHeat) {
  thermal_cylinder("tet10 heat", "tet", 2, 2.7, 1.6, true);
}

// ------------------------------------------------------------------------------------------
// Temperature-dependent E and α (ν constant), tables in the case.

/// Piecewise-linear interpolation with end values outside, written here independently of the
/// solver's PropertyTable.
double interp(const std::vector<double>& t, const std::vector<double>& v, double T) {
  if (T <= t.front()) return v.front();
  if (T >= t.back()) return v.back();
  std::size_t j = 1;
  while (t[j] < T) ++j;
  return v[j - 1] + (v[j] - v[j - 1]) * (T - t[j - 1]) / (t[j] - t[j - 1]);
}

const std::vector<double> E_T{0, 200, 600}, E_v{2.1e11, 1.9e11, 1.5e11};
const std::vector<double> a_T{0, 600}, a_v{1.1e-5, 1.5e-5};
constexpr double T_ref = 20;

std::string table_case(const std::string& mesh_file, const std::string& field, int steps,
                       double correction, const std::string& boundary) {
  return fmt::format(
      "title: temperature-dependent properties\nmesh:\n  file: {}\n"
      "materials:\n  - name: m\n"
      "    E: {{temperature: [{}, {}, {}], value: [{}, {}, {}]}}\n"
      "    nu: {}\n"
      "    alpha: {{temperature: [{}, {}], value: [{}, {}]}}\n"
      "temperature:\n  reference: {}\n  field: \"{}\"\n"
      "boundary:\n{}"
      "solver:\n  steps: {}\n  end: 1\n  correction: {}\n",
      mesh_file, num(E_T[0]), num(E_T[1]), num(E_T[2]), num(E_v[0]), num(E_v[1]), num(E_v[2]), num(nu),
      num(a_T[0]), num(a_T[1]), num(a_v[0]), num(a_v[1]), num(T_ref), field, boundary, steps,
      num(correction));
}

double max_stress_difference(const State& a, const State& b, double scale) {
  double d = 0;
  for (std::size_t q = 0; q < a.stress.size(); ++q)
    d = std::max(d, (a.stress[q] - b.stress[q]).lpNorm<Eigen::Infinity>());
  return d / scale;
}

double max_u_difference(const State& a, const State& b) {
  double d = 0, m = 0;
  for (std::size_t i = 0; i < a.u.size(); ++i) {
    d = std::max(d, std::abs(a.u[i] - b.u[i]));
    m = std::max(m, std::abs(a.u[i]));
  }
  return d / m;
}

// Uniform heating 20 -> 420 in 1 and in 8 steps (the path crosses the E-table point 200):
// the fully constrained body ends at σ_ii = −E(T) (α(T) T − α(T_ref) T_ref) / (1 − 2ν) either
// way; the bar held only axially ends at σ_xx = −E(T) θ, u_y = (1+ν) θ y.
TEST(VerifyTemperatureTables, ConstrainedBarPathIndependentAndClosedForm) {
  const double T1 = 420;
  const double theta = interp(a_T, a_v, T1) * T1 - interp(a_T, a_v, T_ref) * T_ref;
  const double E1 = interp(E_T, E_v, T1);
  const double s_full = -E1 * theta / (1 - 2 * nu), s_axial = -E1 * theta;

  // What the step-by-step update would give without the ΔA·σ term of (1.9): the sum of
  // D(T_k) Δ(αT)_k. Shows the margin by which the tests below detect a missing term.
  double naive = 0;
  for (int k = 1; k <= 8; ++k) {
    const double Ta = T_ref + 400.0 * (k - 1) / 8, Tb = T_ref + 400.0 * k / 8;
    naive -= interp(E_T, E_v, Tb) / (1 - 2 * nu) * (interp(a_T, a_v, Tb) * Tb - interp(a_T, a_v, Ta) * Ta);
  }
  report(fmt::format("temperature tables: closed form sigma_ii {:.9e}; without the dA*sigma term 8 steps "
                     "would give {:.9e} (rel diff {:.2e})",
                     s_full, naive, naive / s_full - 1));

  TempDir dir("temperature-tables");
  write_file(dir / "cube.msh", cube_msh(3, GridCells::hex8, 0.25));
  const std::string field = "20 + 400*t";
  const std::string axial = "  - region: x0\n    displacement: {x: 0}\n  - region: x1\n    displacement: {x: 0}\n"
                            "  - region: y0\n    displacement: {y: 0}\n  - region: z0\n    displacement: {z: 0}\n";
  for (const auto& [label, boundary] : {std::pair<std::string, std::string>{"full", rollers},
                                        std::pair<std::string, std::string>{"axial", axial}}) {
    auto one = run_case(dir.path(), table_case("cube.msh", field, 1, 1.0, boundary), label + "1.yaml");
    auto eight = run_case(dir.path(), table_case("cube.msh", field, 8, 1.0, boundary), label + "8.yaml");
    ASSERT_EQ(eight->run->states.reports.size(), 8u);
    const bool full = label == "full";
    Voigt expect;
    if (full)
      expect << s_full, s_full, s_full, 0, 0, 0;
    else
      expect << s_axial, 0, 0, 0, 0, 0;
    const double scale = std::abs(full ? s_full : s_axial);
    double err1 = 0, err8 = 0;
    for (std::size_t q = 0; q < one->state().stress.size(); ++q) {
      err1 = std::max(err1, (one->state().stress[q] - expect).lpNorm<Eigen::Infinity>() / scale);
      err8 = std::max(err8, (eight->state().stress[q] - expect).lpNorm<Eigen::Infinity>() / scale);
    }
    double uerr = 0;
    const Mesh& mesh = eight->model().mesh();
    for (int n = 0; n < mesh.n_nodes(); ++n) {
      const Vec3 x = mesh.x[n];
      const Vec3 ue = full ? Vec3::Zero() : Vec3(0, (1 + nu) * theta * x.y(), (1 + nu) * theta * x.z());
      uerr = std::max(uerr, (eight->u(n) - ue).lpNorm<Eigen::Infinity>() / ((1 + nu) * theta));
    }
    const double path = max_stress_difference(one->state(), eight->state(), scale);
    report(fmt::format("temperature tables {:<5}: 1 step vs closed form {:.2e}, 8 steps vs closed form {:.2e}, "
                       "8 vs 1 step {:.2e}, u (8 steps) vs closed form {:.2e}",
                       label, err1, err8, path, uerr));
    EXPECT_LT(err1, 1e-10) << label;
    EXPECT_LT(err8, 1e-10) << label;
    EXPECT_LT(path, 1e-10) << label;
    EXPECT_LT(uerr, 1e-10) << label;
  }
}

// A non-uniform temperature (so E varies in space and the answer needs the global solve) on a
// distorted quadratic mesh: 1 step, 8 steps, and 8 steps without the error correction all give
// the same elastic answer. The correction only removes an equilibrium defect, and a linear
// step leaves none.
TEST(VerifyTemperatureTables, NonUniformTemperatureStepsAndCorrection) {
  TempDir dir("temperature-tables-nonuniform");
  write_file(dir / "cube.msh", cube_msh(3, GridCells::hex20, 0.25));
  const std::string field = "20 + 500*t*(0.2 + 0.3*x + 0.3*y*z)";
  const std::string boundary = "  - region: x0\n    displacement: {x: 0}\n  - region: y0\n    displacement: {y: 0}\n"
                               "  - region: z0\n    displacement: {z: 0}\n";
  auto one = run_case(dir.path(), table_case("cube.msh", field, 1, 1.0, boundary), "one.yaml");
  auto eight = run_case(dir.path(), table_case("cube.msh", field, 8, 1.0, boundary), "eight.yaml");
  auto eight0 = run_case(dir.path(), table_case("cube.msh", field, 8, 0.0, boundary), "eight0.yaml");
  double scale = 0;
  for (const Voigt& s : one->state().stress) scale = std::max(scale, s.lpNorm<Eigen::Infinity>());
  const double ds8 = max_stress_difference(one->state(), eight->state(), scale);
  const double ds0 = max_stress_difference(eight->state(), eight0->state(), scale);
  const double du8 = max_u_difference(one->state(), eight->state());
  const double du0 = max_u_difference(eight->state(), eight0->state());
  report(fmt::format("temperature tables non-uniform hex20: max|sigma| {:.4e}; 8 vs 1 step: dsigma {:.2e} du {:.2e}; "
                     "correction 0 vs 1: dsigma {:.2e} du {:.2e}",
                     scale, ds8, du8, ds0, du0));
  EXPECT_GT(scale, 1e7);  // the case does carry thermal stress
  EXPECT_LT(ds8, 1e-10);
  EXPECT_LT(du8, 1e-10);
  EXPECT_LT(ds0, 1e-10);
  EXPECT_LT(du0, 1e-10);
}

}  // namespace
