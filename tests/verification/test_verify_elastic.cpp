// Verification of the elastic solution against closed forms: the Lamé thick cylinder (plane
// strain) and the thick sphere under internal pressure with observed L2 convergence rates,
// a cantilever against Timoshenko beam theory, global equilibrium of the reactions, and the
// iterative linear solver against the direct one.
#include <gtest/gtest.h>

#include "verify_support.hpp"

using namespace hencky;
using namespace hencky::verify;

namespace {

constexpr double E = 2.0e11, nu = 0.3;

std::string material_yaml() {
  return fmt::format("materials:\n  - name: steel\n    E: {}\n    nu: {}\n", num(E), num(nu));
}

// ------------------------------------------------------------------------------------------
// Lamé: thick cylinder a <= r <= b under internal pressure p, plane strain (ε_z = 0).
//   u_r = (1+ν) p a² / (E (b² − a²)) · ((1 − 2ν) r + b² / r)
//   σ_r = p a²/(b² − a²) (1 − b²/r²), σ_θ = p a²/(b² − a²) (1 + b²/r²), σ_z = ν (σ_r + σ_θ)
struct Lame {
  double a = 1.0, b = 2.0, p = 100e6;
  Vec3 u(const Vec3& x) const {
    const double r = std::hypot(x.x(), x.y());
    const double ur = (1 + nu) * p * a * a / (E * (b * b - a * a)) * ((1 - 2 * nu) * r + b * b / r);
    return {ur * x.x() / r, ur * x.y() / r, 0.0};
  }
  Voigt stress(const Vec3& x) const {
    const double r2 = x.x() * x.x() + x.y() * x.y(), k = p * a * a / (b * b - a * a);
    const double sr = k * (1 - b * b / r2), st = k * (1 + b * b / r2);
    const double c2 = x.x() * x.x() / r2, s2 = x.y() * x.y() / r2, cs = x.x() * x.y() / r2;
    Voigt s;
    s << sr * c2 + st * s2, sr * s2 + st * c2, nu * (sr + st), 0, 0, (sr - st) * cs;
    return s;
  }
};

/// The quarter-ring slice: nr elements through the wall, 2 nr around, one layer of thickness
/// (b − a)/nr; symmetry planes and both faces held axially (plane strain).
std::string lame_case(const Lame& L, int order, const std::string& linear = "direct") {
  return fmt::format(
      "title: Lame cylinder\nmesh:\n  file: ring.geo\n  order: {}\n{}boundary:\n"
      "  - region: inner\n    pressure: {}\n"
      "  - region: xsym\n    displacement: {{x: 0}}\n"
      "  - region: ysym\n    displacement: {{y: 0}}\n"
      "  - region: bottom\n    displacement: {{z: 0}}\n"
      "  - region: top\n    displacement: {{z: 0}}\n"
      "solver:\n  linear: {}\n",
      order, material_yaml(), num(L.p), linear);
}

struct LameResult {
  double h, u_error, stress_error;
  int cells;
};

LameResult run_lame(const std::string& cells, int order, int nr) {
  const Lame L;
  TempDir dir(fmt::format("lame-{}{}-{}", cells, order, nr));
  write_file(dir / "ring.geo", quarter_ring_geo(L.a, L.b, (L.b - L.a) / nr, nr, 2 * nr, cells));
  auto r = run_case(dir.path(), lame_case(L, order));
  const L2Norms n = l2_displacement_error(r->model(), r->state(), [&](const Vec3& x) { return L.u(x); });
  const double se = l2_stress_error(r->model(), r->state(), [&](const Vec3& x) { return L.stress(x); });
  return {(L.b - L.a) / nr, n.relative(), se, n.cells};
}

struct RateCase {
  std::string label, cells;
  int order;
  std::vector<int> nr;
  double min_rate;      ///< lower bound on the observed displacement rate
  double finest_error;  ///< upper bound on the finest relative L2 error
};

void lame_convergence(const RateCase& rc) {
  std::vector<double> h, e;
  for (int nr : rc.nr) {
    const LameResult res = run_lame(rc.cells, rc.order, nr);
    h.push_back(res.h);
    e.push_back(res.u_error);
    report(fmt::format("lame {:<6} nr {:2d} cells {:5d} h {:.4f}  L2(u) rel {:.3e}  L2(sigma) rel {:.3e}",
                       rc.label, nr, res.cells, res.h, res.u_error, res.stress_error));
  }
  const double rate = observed_rate(h, e);
  const double last_rate = std::log(e[e.size() - 2] / e.back()) / std::log(h[h.size() - 2] / h.back());
  report(fmt::format("lame {:<6} observed L2(u) rate {:.3f} (last pair {:.3f})", rc.label, rate, last_rate));
  ::testing::Test::RecordProperty("rate", fmt::format("{:.3f}", rate));
  ::testing::Test::RecordProperty("finest_error", fmt::format("{:.3e}", e.back()));
  for (std::size_t i = 1; i < e.size(); ++i) EXPECT_LT(e[i], e[i - 1]);
  EXPECT_GT(rate, rc.min_rate);
  EXPECT_GT(last_rate, rc.min_rate);
  EXPECT_LT(e.back(), rc.finest_error);
}

// Linear elements: O(h²) in L2 (the polygonal boundary is also O(h²)); quadratic
// (isoparametric, curved boundary): O(h³). Bands: asymptotic rate − 0.2 / − 0.3.
TEST(VerifyLame, Hex8RateTwo) { lame_convergence({"hex8", "hex", 1, {2, 4, 8}, 1.8, 5e-3}); }
TEST(VerifyLame, Wedge6RateTwo) { lame_convergence({"wedge6", "wedge", 1, {4, 8, 16}, 1.8, 5e-3}); }
TEST(VerifyLame, Hex20RateThree) { lame_convergence({"hex20", "hex", 2, {2, 4, 8}, 2.7, 1e-4}); }
TEST(VerifyLame, Tet10RateThree) { lame_convergence({"tet10", "tet", 2, {2, 4, 8}, 2.7, 1e-4}); }

// ------------------------------------------------------------------------------------------
// Thick sphere a <= r <= b under internal pressure p (one eighth, three symmetry planes):
//   u_r = p a³ r / (E (b³ − a³)) · ((1 − 2ν) + (1 + ν) b³ / (2 r³))
//   σ_r = −p a³ (b³ − r³) / (r³ (b³ − a³)),  σ_θ = p a³ (b³ + 2 r³) / (2 r³ (b³ − a³))
struct Sphere {
  double a = 1.0, b = 2.0, p = 100e6;
  Vec3 u(const Vec3& x) const {
    const double r = x.norm(), a3 = a * a * a, b3 = b * b * b;
    const double ur = p * a3 * r / (E * (b3 - a3)) * ((1 - 2 * nu) + (1 + nu) * b3 / (2 * r * r * r));
    return ur * x / r;
  }
  Voigt stress(const Vec3& x) const {
    const double r = x.norm(), r3 = r * r * r, a3 = a * a * a, b3 = b * b * b;
    const double sr = -p * a3 * (b3 - r3) / (r3 * (b3 - a3));
    const double st = p * a3 * (b3 + 2 * r3) / (2 * r3 * (b3 - a3));
    const Vec3 n = x / r;
    const Mat3 S = st * Mat3::Identity() + (sr - st) * n * n.transpose();
    Voigt s;
    s << S(0, 0), S(1, 1), S(2, 2), S(1, 2), S(2, 0), S(0, 1);
    return s;
  }
};

std::string sphere_geo(const Sphere& S, double h) {
  return fmt::format(R"(SetFactory("OpenCASCADE");
a = {}; b = {}; h = {};
Mesh.CharacteristicLengthMax = h;
Mesh.MeshSizeFromPoints = 0;  // the OCC sphere's points carry small sizes of their own
Sphere(1) = {{0, 0, 0, b, 0, Pi/2, Pi/2}};
Sphere(2) = {{0, 0, 0, a, 0, Pi/2, Pi/2}};
BooleanDifference(3) = {{ Volume{{1}}; Delete; }}{{ Volume{{2}}; Delete; }};
e = 1e-3;
Physical Volume("body") = {{3}};
Physical Surface("inner") = Surface In BoundingBox{{-e, -e, -e, a + e, a + e, a + e}};
Physical Surface("xsym") = Surface In BoundingBox{{-e, -e, -e, e, b + e, b + e}};
Physical Surface("ysym") = Surface In BoundingBox{{-e, -e, -e, b + e, e, b + e}};
Physical Surface("zsym") = Surface In BoundingBox{{-e, -e, -e, b + e, b + e, e}};
)",
                     num(S.a), num(S.b), num(h));
}

// Unstructured tet10 (curved isoparametric boundary) at three sizes; the mesh size is the
// mean cell size (V / cells)^(1/3), as the meshes are not nested.
TEST(VerifySphere, Tet10InternalPressureRateThree) {
  const Sphere S;
  std::vector<double> h, e;
  for (double size : {0.3, 0.2, 0.15}) {
    TempDir dir("sphere");
    write_file(dir / "sphere.geo", sphere_geo(S, size));
    auto r = run_case(dir.path(), fmt::format("title: thick sphere\nmesh:\n  file: sphere.geo\n  order: 2\n{}"
                                              "boundary:\n  - region: inner\n    pressure: {}\n"
                                              "  - region: xsym\n    displacement: {{x: 0}}\n"
                                              "  - region: ysym\n    displacement: {{y: 0}}\n"
                                              "  - region: zsym\n    displacement: {{z: 0}}\n",
                                              material_yaml(), num(S.p)));
    const L2Norms n = l2_displacement_error(r->model(), r->state(), [&](const Vec3& x) { return S.u(x); });
    const double se = l2_stress_error(r->model(), r->state(), [&](const Vec3& x) { return S.stress(x); });
    // The volume by quadrature must be the shell's: checks the curved geometry itself.
    const double v_exact = std::acos(-1.0) / 6 * (S.b * S.b * S.b - S.a * S.a * S.a);
    report(fmt::format("sphere tet10 size {:.2f} cells {:5d} h_mean {:.4f}  L2(u) rel {:.3e}  "
                       "L2(sigma) rel {:.3e}  volume rel err {:.1e}",
                       size, n.cells, n.h(), n.relative(), se, n.volume / v_exact - 1));
    EXPECT_NEAR(n.volume / v_exact, 1.0, 1e-2);
    h.push_back(n.h());
    e.push_back(n.relative());
  }
  const double rate = observed_rate(h, e);
  report(fmt::format("sphere tet10 observed L2(u) rate {:.3f}", rate));
  RecordProperty("rate", fmt::format("{:.3f}", rate));
  for (std::size_t i = 1; i < e.size(); ++i) EXPECT_LT(e[i], e[i - 1]);
  EXPECT_GT(rate, 2.5);  // unstructured, non-nested meshes: see docs/verification.md
  EXPECT_LT(e.back(), 1e-3);
}

// ------------------------------------------------------------------------------------------
// Cantilever L x W x H clamped at x = 0 (every displacement 0), total force P along −z spread
// over the end face. Timoshenko beam theory: δ = P L³ / (3 E I) + P L / (κ G A) with Cowper's
// shear coefficient κ = 10 (1 + ν) / (12 + 11 ν) for a rectangle.
TEST(VerifyCantilever, Hex20TipDeflectionTimoshenko) {
  const double L = 2.0, W = 0.1, H = 0.1, P = 1000.0;
  const double I = W * H * H * H / 12, A = W * H, G = E / (2 * (1 + nu));
  const double kappa = 10 * (1 + nu) / (12 + 11 * nu);
  const double bending = P * L * L * L / (3 * E * I), shear = P * L / (kappa * G * A);
  const double timoshenko = bending + shear;
  std::vector<double> tip;
  for (auto [nl, nh] : {std::pair{20, 1}, std::pair{40, 2}, std::pair{80, 4}}) {
    TempDir dir("cantilever");
    write_file(dir / "beam.geo",
               fmt::format(R"(L = {}; W = {}; H = {};
Point(1) = {{0, 0, 0}}; Point(2) = {{0, W, 0}}; Point(3) = {{0, W, H}}; Point(4) = {{0, 0, H}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
Transfinite Curve{{1:4}} = {}; Transfinite Surface{{1}}; Recombine Surface{{1}};
out[] = Extrude {{L, 0, 0}} {{ Surface{{1}}; Layers{{{}}}; Recombine; }};
Physical Volume("beam") = {{out[1]}};
Physical Surface("fixed") = {{1}};
Physical Surface("tip") = {{out[0]}};
)",
                           num(L), num(W), num(H), nh + 1, nl));
    auto r = run_case(dir.path(),
                      fmt::format("title: cantilever\nmesh:\n  file: beam.geo\n  order: 2\n{}"
                                  "boundary:\n  - region: fixed\n    displacement: {{x: 0, y: 0, z: 0}}\n"
                                  "  - region: tip\n    force: [0, 0, {}]\n"
                                  "output:\n  probes:\n    - name: tip\n      point: [{}, {}, {}]\n",
                                  material_yaml(), num(-P), num(L), num(W / 2), num(H / 2)));
    const auto& model = r->model();
    const ProbeValues v = probe_values(model, model.probes().at(0), r->state(),
                                       recover_nodal_stress(model, r->state()));
    tip.push_back(-v.displacement.z());
    report(fmt::format("cantilever hex20 {:2d} x {}x{} cells: tip deflection {:.6e}  Timoshenko {:.6e} "
                       "(bending {:.4e} + shear {:.4e})  rel diff {:+.3e}",
                       nl, nh, nh, tip.back(), timoshenko, bending, shear, tip.back() / timoshenko - 1));
  }
  const double diff = std::abs(tip.back() / timoshenko - 1);
  // Richardson extrapolation with the observed order, to show where the 3D answer converges.
  const double order = std::log2((tip[1] - tip[0]) / (tip[2] - tip[1]));
  const double limit = tip[2] + (tip[2] - tip[1]) / (std::pow(2.0, order) - 1);
  report(fmt::format("cantilever hex20 observed order {:.2f}, extrapolated tip {:.6e} (rel diff {:+.3e})",
                     order, limit, limit / timoshenko - 1));
  RecordProperty("tip_rel_difference", fmt::format("{:.3e}", diff));
  EXPECT_LT(diff, 1e-2);
  // Converging: successive changes shrink.
  EXPECT_LT(std::abs(tip[2] - tip[1]), std::abs(tip[1] - tip[0]));
}

// ------------------------------------------------------------------------------------------
// Global equilibrium: with pressure (varying over the face), traction (varying), a total force
// and a body force (varying), the reactions of all supported regions balance the applied load:
// Σ R + F = 0. Every load integral is of a polynomial the rules integrate exactly in sum
// (Σ_a N_a = 1), so F is known in closed form.
TEST(VerifyEquilibrium, ReactionsBalanceAllLoadKinds) {
  const double Lx = 1.0, Ly = 0.5, Lz = 0.4;
  TempDir dir("equilibrium");
  write_file(dir / "box.geo", box_geo(Lx, Ly, Lz, 0.15));
  const std::string head = fmt::format("title: equilibrium\nmesh:\n  file: box.geo\n  order: 2\n{}", material_yaml());
  auto r = run_case(dir.path(),
                    head + "boundary:\n"
                           "  - region: x0\n    displacement: {x: 0, y: 0, z: 0}\n"
                           "  - region: p100\n    displacement: {z: 0}\n"
                           "  - region: x1\n    pressure: \"2e6*(1 + y)\"\n"
                           "  - region: y1\n    traction: [1e5, 0, \"3e5*x\"]\n"
                           "  - region: z1\n    force: [0, 1e4, -2e4]\n"
                           "body_force: [0, 0, \"-7.85e4*(1 + x)\"]\n"
                           "output:\n  reactions: [x0, p100]\n");
  // Closed-form totals of each load.
  const Vec3 pressure(-2e6 * Lz * (Ly + Ly * Ly / 2), 0, 0);  // −∫ p n dA, n = +x
  const Vec3 traction(1e5 * Lx * Lz, 0, 3e5 * Lz * Lx * Lx / 2);
  const Vec3 force(0, 1e4, -2e4);
  const Vec3 body(0, 0, -7.85e4 * Ly * Lz * (Lx + Lx * Lx / 2));
  const Vec3 F = pressure + traction + force + body;
  const double scale = pressure.norm() + traction.norm() + force.norm() + body.norm();

  const State& s = r->state();
  Vec3 f_ext = Vec3::Zero();
  for (int n = 0; n < r->model().mesh().n_nodes(); ++n)
    f_ext += Vec3(s.f_ext[3 * n], s.f_ext[3 * n + 1], s.f_ext[3 * n + 2]);
  Vec3 R = Vec3::Zero();
  for (const Vec3& f : region_reactions(r->model(), s)) R += f;
  // The same from the prescribed dofs directly.
  Vec3 R_dofs = Vec3::Zero();
  for (int i = 0; i < r->model().dofs().n_dofs(); ++i)
    if (r->model().dofs().eq[i] < 0) R_dofs[i % 3] += s.f_int[i] - s.f_ext[i];
  report(fmt::format("equilibrium tet10: |sum f_ext - F|/|F| {:.2e}  |sum R + F|/|F| {:.2e}  "
                     "|R(dofs) + F|/|F| {:.2e}",
                     (f_ext - F).norm() / scale, (R + F).norm() / scale, (R_dofs + F).norm() / scale));
  RecordProperty("balance", fmt::format("{:.3e}", (R + F).norm() / scale));
  EXPECT_LT((f_ext - F).norm() / scale, 1e-12);
  EXPECT_LT((R + F).norm() / scale, 1e-8);
  EXPECT_LT((R_dofs + F).norm() / scale, 1e-8);
}

// A total `force` is spread by area: whatever the mesh, its nodal forces add up to the given
// force, and the support carries exactly its opposite.
TEST(VerifyEquilibrium, ForceRegionTotalIsTheGivenForce) {
  TempDir dir("force-total");
  write_file(dir / "cube.msh", cube_msh(3, GridCells::hex20, 0.25));
  const Vec3 force(3e3, -7e3, 11e3);
  auto r = run_case(dir.path(),
                    fmt::format("title: force total\nmesh:\n  file: cube.msh\n{}boundary:\n"
                                "  - region: x0\n    displacement: {{x: 0, y: 0, z: 0}}\n"
                                "  - region: x1\n    force: [{}, {}, {}]\n"
                                "output:\n  reactions: [x0]\n",
                                material_yaml(), num(force[0]), num(force[1]), num(force[2])));
  const Region* x1 = r->model().mesh().find_region("x1");
  ASSERT_NE(x1, nullptr);
  Vec3 total = Vec3::Zero();
  for (int n : x1->nodes) total += Vec3(r->state().f_ext[3 * n], r->state().f_ext[3 * n + 1], r->state().f_ext[3 * n + 2]);
  const Vec3 R = region_reactions(r->model(), r->state()).at(0);
  report(fmt::format("force region hex20: |sum f - F|/|F| {:.2e}  |R + F|/|F| {:.2e}",
                     (total - force).norm() / force.norm(), (R + force).norm() / force.norm()));
  EXPECT_LT((total - force).norm() / force.norm(), 1e-12);
  EXPECT_LT((R + force).norm() / force.norm(), 1e-8);
}

// ------------------------------------------------------------------------------------------
// Elastic load-unload: a uniform tension ramped up to t = 1 and back to zero at t = 2 must end
// exactly where it started (u = 0, σ = 0) in the two requested steps.
TEST(VerifyUnloading, BackToZeroLoadEndsUndeformed) {
  TempDir dir("unload");
  write_file(dir / "cube.msh", cube_msh(2, GridCells::hex8, 0.2));
  auto r = run_case(dir.path(), fmt::format("title: unload\nmesh:\n  file: cube.msh\n{}boundary:\n"
                                            "  - region: x0\n    displacement: {{x: 0}}\n"
                                            "  - region: y0\n    displacement: {{y: 0}}\n"
                                            "  - region: z0\n    displacement: {{z: 0}}\n"
                                            "  - region: x1\n    traction: [\"t <= 1 ? 1e7*t : 1e7*(2 - t)\", 0, 0]\n"
                                            "solver:\n  times: [1, 2]\n",
                                            material_yaml()));
  EXPECT_EQ(r->run->states.reports.size(), 2u);
  double umax = 0, smax = 0;
  for (double u : r->state().u) umax = std::max(umax, std::abs(u));
  for (const Voigt& q : r->state().stress) smax = std::max(smax, q.lpNorm<Eigen::Infinity>());
  EXPECT_LT(umax, 1e-12 * 1e7 / E);
  EXPECT_LT(smax, 1e-10 * 1e7);
}

// The same cylinder with the CG back end: agrees with CHOLMOD to far better than 1e-6.
TEST(VerifyIterativeSolver, LameCylinderMatchesDirect) {
  const Lame L;
  const int nr = 3;
  TempDir dir("lame-iterative");
  write_file(dir / "ring.geo", quarter_ring_geo(L.a, L.b, (L.b - L.a) / nr, nr, 2 * nr, "hex"));
  auto direct = run_case(dir.path(), lame_case(L, 2, "direct"), "direct.yaml");
  auto iterative = run_case(dir.path(), lame_case(L, 2, "iterative"), "iterative.yaml");
  const auto& ud = direct->state().u;
  const auto& ui = iterative->state().u;
  ASSERT_EQ(ud.size(), ui.size());
  double du = 0, umax = 0;
  for (std::size_t i = 0; i < ud.size(); ++i) {
    du = std::max(du, std::abs(ud[i] - ui[i]));
    umax = std::max(umax, std::abs(ud[i]));
  }
  double ds = 0, smax = 0;
  for (std::size_t q = 0; q < direct->state().stress.size(); ++q) {
    ds = std::max(ds, (direct->state().stress[q] - iterative->state().stress[q]).lpNorm<Eigen::Infinity>());
    smax = std::max(smax, direct->state().stress[q].lpNorm<Eigen::Infinity>());
  }
  report(fmt::format("iterative vs direct (Lame hex20 nr {}): max|du|/max|u| {:.2e}  "
                     "max|dsigma|/max|sigma| {:.2e}",
                     nr, du / umax, ds / smax));
  ::testing::Test::RecordProperty("u_rel_difference", fmt::format("{:.3e}", du / umax));
  EXPECT_LT(du / umax, 1e-6);
  EXPECT_LT(ds / smax, 1e-6);
}

}  // namespace
