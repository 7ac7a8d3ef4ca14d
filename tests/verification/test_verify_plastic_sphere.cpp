// Verification of plasticity at structure level: the elastic-perfectly-plastic thick-walled
// sphere a < r < b under internal pressure p (Hill, The Mathematical Theory of Plasticity, 1950,
// ch. V, the expanding spherical shell), against its closed form, on an octant with symmetry
// rollers.
//
// The closed form. Spherical symmetry gives σ_θ = σ_φ, so the von Mises and the Tresca
// conditions coincide, σ̃ = σ_θ − σ_r = σ_y, and the solution below is exact for the von Mises
// material of hencky (unlike the plane-strain cylinder, no assumption on an axial stress).
//  - Plastic zone a < r < c: equilibrium dσ_r/dr = 2(σ_θ − σ_r)/r = 2σ_y/r with σ_r(a) = −p:
//      σ_r = −p + 2σ_y ln(r/a),   σ_θ = σ_r + σ_y.
//  - Elastic zone c < r < b: a Lamé shell under the pressure q at r = c, free at r = b:
//      σ_r = −q (b³/r³ − 1)/(b³/c³ − 1),  σ_θ = q (b³/(2r³) + 1)/(b³/c³ − 1),
//      u   = q c³/(E(b³ − c³)) [(1 − 2ν) r + (1 + ν) b³/(2r²)].
//    The shell yields first at its bore: σ_θ − σ_r = (3/2) q b³/(b³ − c³) = σ_y, so
//      q = (2σ_y/3)(1 − c³/b³).
//  - Continuity of σ_r at r = c:  p(c) = 2σ_y ln(c/a) + (2σ_y/3)(1 − c³/b³).
//    First yield (c = a): p_e = (2σ_y/3)(1 − a³/b³); limit load (c = b): p_L = 2σ_y ln(b/a).
//  - Outer displacement (elastic zone, q substituted): u(b) = (1 − ν) σ_y c³ / (E b²);
//    before yield u(b) = 3(1 − ν) p a³ b / (2E(b³ − a³)).
//  - Hoop stress at the bore: σ_θ(a) = σ_y − p (plastic); p(b³ + 2a³)/(2(b³ − a³)) (elastic).
// Under the monotone ramp no point unloads (c grows with p), so the stresses are statically
// determined in the plastic zone and the elastic zone is exactly the Lamé shell: u(b) is exact
// for any ν (small strains).
#include <gtest/gtest.h>

#include "verify_support.hpp"

namespace hencky::verify {
namespace {

struct HillSphere {
  double a = 0.1, b = 0.2, E = 2e11, nu = 0.3, sy = 2.4e8;

  double p_of_c(double c) const {
    return 2 * sy * std::log(c / a) + 2 * sy / 3 * (1 - std::pow(c / b, 3));
  }
  double first_yield() const { return p_of_c(a); }
  double limit() const { return 2 * sy * std::log(b / a); }
  /// Radius of the plastic front; a before first yield.
  double c_of_p(double p) const {
    if (p <= first_yield()) return a;
    double lo = a, hi = b;  // p_of_c increases on [a, b]: dp/dc = 2σ_y(1/c − c²/b³) > 0
    for (int i = 0; i < 200; ++i) {
      const double m = 0.5 * (lo + hi);
      (p_of_c(m) < p ? lo : hi) = m;
    }
    return 0.5 * (lo + hi);
  }
  double u_outer(double p) const {
    if (p <= first_yield())
      return 3 * (1 - nu) * p * a * a * a * b / (2 * E * (b * b * b - a * a * a));
    const double c = c_of_p(p);
    return (1 - nu) * sy * c * c * c / (E * b * b);
  }
  double hoop_bore(double p) const {
    if (p <= first_yield()) return p * (b * b * b + 2 * a * a * a) / (2 * (b * b * b - a * a * a));
    return sy - p;
  }
  /// Hoop strain u(a)/a at the bore, elastic + plastic: exact before yield (Lamé); after yield
  /// the elastic shell's u(c) carried inwards as u ∝ 1/r² (the plastic zone taken as
  /// incompressible, which neglects its small elastic volume change: an estimate, for a
  /// tolerance only).
  double hoop_strain_bore(double p) const {
    const double c = c_of_p(p), q = p <= first_yield() ? p : 2 * sy / 3 * (1 - std::pow(c / b, 3));
    const double u_c = q * c * c * c / (E * (b * b * b - c * c * c)) *
                       ((1 - 2 * nu) * c + (1 + nu) * b * b * b / (2 * c * c));
    return u_c * c * c / (a * a * a);
  }
  /// σ_r, σ_θ at radius r under the pressure p.
  std::pair<double, double> stress(double p, double r) const {
    const double c = c_of_p(p);
    if (r < c) {
      const double sr = -p + 2 * sy * std::log(r / a);
      return {sr, sr + sy};
    }
    const double q = p <= first_yield() ? p : 2 * sy / 3 * (1 - std::pow(c / b, 3));
    const double k = q / (std::pow(b / c, 3) - 1), br = std::pow(b / r, 3);
    return {-k * (br - 1), k * (br / 2 + 1)};
  }
  /// The Cartesian stress at x: σ_θ I + (σ_r − σ_θ) n nᵀ, Voigt {11, 22, 33, 23, 31, 12}.
  Voigt stress_at(double p, const Vec3& x) const {
    const double r = x.norm();
    const Vec3 n = x / r;
    const auto [sr, st] = stress(p, r);
    const double d = sr - st;
    Voigt s;
    s << st + d * n.x() * n.x(), st + d * n.y() * n.y(), st + d * n.z() * n.z(), d * n.y() * n.z(),
        d * n.z() * n.x(), d * n.x() * n.y();
    return s;
  }
};

/// An octant of the spherical shell a <= r <= b (x, y, z >= 0) in three structured hexahedral
/// blocks (the "cubed sphere": the octant's spherical triangle cut into three quadrilaterals at
/// the midpoints of its edges and its centre (1,1,1)/√3). Every block edge on a sphere is a
/// great-circle arc (centre at the origin), every side face lies in a plane through the origin,
/// so the built-in kernel meshes it transfinitely: n cells along each arc, nr radially.
/// `order: 2` on the mesh key then gives 20-node hexahedra with the mid-edge nodes placed on
/// the spheres by Gmsh.
/// Regions: body; inner, outer (the spheres); xsym (x = 0), ysym (y = 0), zsym (z = 0).
std::string sphere_octant_geo(double a, double b, int n, int nr) {
  return fmt::format(R"(a = {}; b = {}; n = {}; nr = {};
s2 = 1/Sqrt(2); s3 = 1/Sqrt(3);
Point(1) = {{0, 0, 0}};
For k In {{0:1}}
  r = (k == 0) ? a : b;
  o = 10*k;
  Point(o+2) = {{r, 0, 0}}; Point(o+3) = {{0, r, 0}}; Point(o+4) = {{0, 0, r}};
  Point(o+5) = {{r*s2, r*s2, 0}}; Point(o+6) = {{0, r*s2, r*s2}}; Point(o+7) = {{r*s2, 0, r*s2}};
  Point(o+8) = {{r*s3, r*s3, r*s3}};
  // great-circle arcs: X-mXY, mXY-Y, Y-mYZ, mYZ-Z, Z-mZX, mZX-X, C-mXY, C-mYZ, C-mZX
  Circle(o+1) = {{o+2, 1, o+5}}; Circle(o+2) = {{o+5, 1, o+3}};
  Circle(o+3) = {{o+3, 1, o+6}}; Circle(o+4) = {{o+6, 1, o+4}};
  Circle(o+5) = {{o+4, 1, o+7}}; Circle(o+6) = {{o+7, 1, o+2}};
  Circle(o+7) = {{o+8, 1, o+5}}; Circle(o+8) = {{o+8, 1, o+6}}; Circle(o+9) = {{o+8, 1, o+7}};
  // the three spherical quadrilaterals (X, mXY, C, mZX), (Y, mYZ, C, mXY), (Z, mZX, C, mYZ)
  Curve Loop(o+1) = {{o+1, -(o+7), o+9, o+6}}; Surface(o+1) = {{o+1}} In Sphere {{1}};
  Curve Loop(o+2) = {{o+3, -(o+8), o+7, o+2}}; Surface(o+2) = {{o+2}} In Sphere {{1}};
  Curve Loop(o+3) = {{o+5, -(o+9), o+8, o+4}}; Surface(o+3) = {{o+3}} In Sphere {{1}};
EndFor
For p In {{2:8}}
  Line(100+p) = {{p, p+10}};
EndFor
// one plane side face per arc i, between its end points
ends[] = {{2,5, 5,3, 3,6, 6,4, 4,7, 7,2, 8,5, 8,6, 8,7}};
For i In {{1:9}}
  p = ends[2*(i-1)]; q = ends[2*(i-1)+1];
  Curve Loop(200+i) = {{i, 100+q, -(10+i), -(100+p)}};
  Plane Surface(200+i) = {{200+i}};
EndFor
Surface Loop(1) = {{1, 11, 201, 207, 209, 206}}; Volume(1) = {{1}};
Surface Loop(2) = {{2, 12, 203, 208, 207, 202}}; Volume(2) = {{2}};
Surface Loop(3) = {{3, 13, 205, 209, 208, 204}}; Volume(3) = {{3}};
Transfinite Curve{{1:9, 11:19}} = n + 1;
Transfinite Curve{{102:108}} = nr + 1;
Transfinite Surface{{1:3, 11:13, 201:209}};
Recombine Surface{{1:3, 11:13, 201:209}};
Transfinite Volume{{1:3}};
Physical Volume("body") = {{1:3}};
Physical Surface("inner") = {{1:3}};
Physical Surface("outer") = {{11:13}};
Physical Surface("zsym") = {{201, 202}};
Physical Surface("xsym") = {{203, 204}};
Physical Surface("ysym") = {{205, 206}};
)",
                     num(a), num(b), n, nr);
}

/// The case: perfect plasticity, rollers on the three symmetry planes, p = p_end·t on the bore.
std::string sphere_case(const HillSphere& h, double p_end, const std::string& steps) {
  return fmt::format(
      "mesh: {{file: sphere.geo, order: 2}}\n"
      "materials:\n  - {{E: {}, nu: {}, plasticity: {{perfect: {{yield: {}}}}}}}\n"
      "boundary:\n"
      "  - {{region: xsym, displacement: {{x: 0}}}}\n"
      "  - {{region: ysym, displacement: {{y: 0}}}}\n"
      "  - {{region: zsym, displacement: {{z: 0}}}}\n"
      "  - {{region: inner, pressure: \"{}*t\"}}\n"
      "solver: {{scheme: newton, {}, tolerance: 1e-8, max_iterations: 60, cutback: 3}}\n"
      "output:\n  probes:\n    - {{name: bore, point: [{}, 0, 0]}}\n",
      num(h.E), num(h.nu), num(h.sy), num(p_end), steps, num(h.a));
}

// The mesh: n = 4 cells along each block arc (8 around a quarter circle, 11.25° each), nr = 8
// radially (h_r = (b − a)/8 = 12.5 mm, 3 Gauss points across each): 384 20-node hexahedra,
// 2010 nodes. Measured in RelWithDebInfo on 2 shared cores: 7-12 s for the ramp to 0.95 p_L,
// 8-14 s for the ramp beyond p_L (most of it in the cut-backs near the limit), depending on
// the load of the machine; the whole file 17-29 s.
constexpr int n_arc = 4, n_rad = 8;

// The closed form checked against itself before it judges the solver: boundary conditions,
// yield and continuity at the front, the limit and first-yield loads, continuity at p_e.
TEST(VerifyPlasticSphere, ClosedFormIsConsistent) {
  const HillSphere h;
  EXPECT_NEAR(h.p_of_c(h.b), h.limit(), 1e-12 * h.sy);
  EXPECT_NEAR(h.first_yield(), 2 * h.sy / 3 * (1 - std::pow(h.a / h.b, 3)), 1e-12 * h.sy);
  for (double f : {0.3, 0.5, 0.7, 0.9, 0.95}) {
    const double p = f * h.limit(), c = h.c_of_p(p);
    EXPECT_NEAR(h.stress(p, h.a).first, -p, 1e-9 * h.sy);   // σ_r(a) = −p
    EXPECT_NEAR(h.stress(p, h.b).first, 0.0, 1e-9 * h.sy);  // σ_r(b) = 0
    EXPECT_NEAR(h.stress(p, h.a).second, h.hoop_bore(p), 1e-9 * h.sy);
    const auto in = h.stress(p, c * (1 - 1e-9)), out = h.stress(p, c * (1 + 1e-9));
    EXPECT_NEAR(in.first, out.first, 1e-6 * h.sy);  // σ_r continuous at the front
    if (p > h.first_yield()) {
      EXPECT_NEAR(in.second - in.first, h.sy, 1e-9 * h.sy);    // yield inside
      EXPECT_NEAR(out.second - out.first, h.sy, 1e-6 * h.sy);  // and just yielding outside
    } else {  // elastic: below yield at the bore, where σ_θ − σ_r is largest
      EXPECT_LT(h.stress(p, h.a).second - h.stress(p, h.a).first, h.sy);
    }
    // u(b) of the Lamé shell under q at c agrees with the closed form (1 − ν)σ_y c³/(E b²)
    const double q = -h.stress(p, c).first;
    const double u_lame = q * c * c * c / (h.E * (std::pow(h.b, 3) - c * c * c)) *
                          ((1 - 2 * h.nu) * h.b + (1 + h.nu) * h.b / 2);
    EXPECT_NEAR(h.u_outer(p), u_lame, 1e-9 * u_lame);
  }
  const double pe = h.first_yield();
  EXPECT_NEAR(h.u_outer(pe * (1 - 1e-12)), h.u_outer(pe * (1 + 1e-12)), 1e-9 * h.u_outer(pe));
  EXPECT_NEAR(h.hoop_bore(pe * (1 - 1e-12)), h.hoop_bore(pe * (1 + 1e-12)), 1e-9 * h.sy);
}

TEST(VerifyPlasticSphere, ThickSphereAgainstHillUpTo95PercentOfTheLimit) {
  const HillSphere h;
  TempDir dir("hill-sphere");
  write_file(dir / "sphere.geo", sphere_octant_geo(h.a, h.b, n_arc, n_rad));
  const double p_end = 0.95 * h.limit();
  // 0.4 p_L is elastic (p_e = 0.42 p_L); then steps of 0.05 p_L and finer near the end.
  std::vector<double> fractions = {0.4,  0.45, 0.5,  0.55, 0.6,   0.65, 0.7,
                                   0.75, 0.8,  0.85, 0.9,  0.925, 0.95};
  std::string times = "times: [";
  for (std::size_t i = 0; i < fractions.size(); ++i) {
    times += i ? ", " : "";
    times += num(fractions[i] / 0.95);
  }
  times += "]";
  auto r = run_stepped(dir.path(), sphere_case(h, p_end, times));
  ASSERT_EQ(r->result.status, AnalysisStatus::converged) << r->result.failure;
  ASSERT_EQ(r->all.states.size(), fractions.size());
  const Model& m = r->model();
  const Mesh& mesh = m.mesh();
  const double h_r = (h.b - h.a) / n_rad;
  const std::vector<Vec3> xq = point_positions(m);
  // the nodes of the outer sphere
  std::vector<int> outer;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (std::abs(mesh.x[i].norm() - h.b) < 1e-9 * h.b) outer.push_back(i);
  ASSERT_GT(outer.size(), 100u);
  double worst_u = 0, worst_hoop = 0;
  for (std::size_t k = 0; k < r->all.states.size(); ++k) {
    const double p = p_end * r->all.reports[k].time;
    const State& s = r->all.states[k];
    const double c = h.c_of_p(p), u_exact = h.u_outer(p);
    // u(b): the radial displacement of every node of the outer sphere (it must be uniform).
    double u_min = 1e30, u_max = -1e30;
    for (int i : outer) {
      const Vec3 x = mesh.x[i];
      const double ur = Vec3(s.u[3 * i], s.u[3 * i + 1], s.u[3 * i + 2]).dot(x) / x.norm();
      u_min = std::min(u_min, ur);
      u_max = std::max(u_max, ur);
    }
    const double u_err = std::max(std::abs(u_min - u_exact), std::abs(u_max - u_exact)) / u_exact;
    // the plastic front: largest radius of a point that has flowed, smallest of one that has not
    double r_in = h.a, r_out = h.b;
    for (std::size_t q = 0; q < xq.size(); ++q) {
      const double rq = xq[q].norm();
      if (s.eps_p_eq[q] > 0)
        r_in = std::max(r_in, rq);
      else
        r_out = std::min(r_out, rq);
    }
    // hoop stress at the bore on the x axis, recovered to the node (σ_yy there)
    const auto nodal = recover_nodal_stress(m, s);
    const ProbeValues bore = probe_values(m, m.probes()[0], s, nodal);
    const double hoop_err = (bore.stress[1] - h.hoop_bore(p)) / h.sy;
    const double l2s = l2_stress_error(m, s, [&](const Vec3& x) { return h.stress_at(p, x); });
    // σ_θ at the integration points of the bore layer (σ_r = nᵀσn, σ_θ = (tr σ − σ_r)/2)
    double bore_pt_err = 0;
    for (std::size_t q = 0; q < xq.size(); ++q) {
      const double rq = xq[q].norm();
      if (rq > h.a + 0.5 * h_r) continue;
      const Vec3 n = xq[q] / rq;
      const Voigt& sg = s.stress[q];
      Mat3 t;
      t << sg[0], sg[5], sg[4], sg[5], sg[1], sg[3], sg[4], sg[3], sg[2];
      const double sr = n.dot(t * n), st = (t.trace() - sr) / 2;
      bore_pt_err = std::max(bore_pt_err, std::abs(st - h.stress(p, rq).second) / h.sy);
    }
    // The error the mesh allows in the stress. At every plastic point the deviator is pinned to
    // the yield surface, so the error is in the mean stress: K times the volumetric strain, a
    // small remainder of a strain field made mostly of the isochoric plastic flow. The
    // 20-node hexahedra interpolate that strain field (∝ r⁻³, linear within an element) with a
    // relative error of order (h_r/r)², so the mean stress may be off by about
    // K·(h_r/a)²·ε_θ(a) at the bore, ε_θ(a) = u(a)/a the hoop strain there (elastic + plastic;
    // 0.44 σ_y/E at 0.4 p_L, before yield; 2.9 σ_y/E at 0.95 p_L): 0.006 σ_y and 0.038 σ_y
    // respectively. Twice that is the tolerance (the estimate gives the order, not a bound;
    // the Gauss points of the bore layer, reported, come out at 1.3-2 times it, the recovered
    // nodal value, checked, at 0.6 times it: the recovery averages the point-to-point scatter).
    // Refining to 6 x 12 cells (tried when this test was written) halves the measured errors
    // ((8/12)² = 0.44): it is this discretization error, not an error of the solver.
    const double K = h.E / (3 * (1 - 2 * h.nu));
    const double stress_tol = 2 * K * std::pow(h_r / h.a, 2) * h.hoop_strain_bore(p) / h.sy;
    report(fmt::format(
        "sphere p/pL {:.3f}  u(b) {:.6e}..{:.6e} (Hill {:.6e}, err {:.3f} %)  "
        "front [{:.4f}, {:.4f}] (Hill {:.4f})  sigma_t(a) {:+.4e} (Hill {:+.4e}, err {:+.4f} sy, "
        "tol {:.4f}; at the bore layer's points {:.4f} sy)  L2(sigma) {:.2f} %",
        p / h.limit(), u_min, u_max, u_exact, 100 * u_err, r_in, r_out, c, bore.stress[1],
        h.hoop_bore(p), hoop_err, stress_tol, bore_pt_err, 100 * l2s));
    worst_u = std::max(worst_u, u_err);
    // u(b): within 1 %. u(b) = (1 − ν)σ_y c³/(E b²) is the elastic shell's answer to the radial
    // stress q at the front, so its relative error is that of σ_r there, divided by q. By the
    // estimate above the mean stress at the front (ε_θ(c) ≈ 0.6 σ_y/E, h_r/c ≥ 0.07) is good
    // to K(h_r/c)²ε_θ(c) ≈ 0.003 σ_y, and q ≥ 0.26 σ_y up to 0.95 p_L: about 1 %. Before yield
    // the Lamé field is resolved to (h_r/a)³ ≈ 2e-3 by the quadratic elements.
    EXPECT_LT(u_err, 0.01) << "p/pL " << p / h.limit();
    if (p > h.first_yield()) {
      // The front lies between the last point that flowed and the first that did not, each
      // within one element (h_r) of the closed form's c.
      EXPECT_GT(r_in, h.a) << "p/pL " << p / h.limit();
      EXPECT_LT(r_in, c + h_r) << "p/pL " << p / h.limit();
      EXPECT_GT(r_out, c - h_r) << "p/pL " << p / h.limit();
      EXPECT_LE(r_in, r_out + h_r) << "p/pL " << p / h.limit();
    } else {
      EXPECT_EQ(r_in, h.a) << "no point may flow below p_e, p/pL " << p / h.limit();
    }
    // σ_θ(a), the nodal value recovered from the Gauss points of the bore elements, within the
    // tolerance above. Not while the front is inside the bore element (p/p_L 0.45-0.55): the
    // stress has a kink there (its slope jumps by 3σ_y/c) that no quadratic field over the
    // element follows, and the extrapolation to the node carries it (measured 0.05 σ_y).
    if (c <= h.a || c > h.a + h_r) {
      worst_hoop = std::max(worst_hoop, std::abs(hoop_err));
      EXPECT_LT(std::abs(hoop_err), stress_tol) << "p/pL " << p / h.limit();
    }
  }
  report(fmt::format(
      "sphere: worst u(b) error {:.3f} %, worst hoop error {:.4f} sy; analysis {:.1f} s, "
      "{} iterations, {} factorizations",
      100 * worst_u, worst_hoop, r->seconds, r->result.iterations, r->result.factorizations));
}

TEST(VerifyPlasticSphere, ThickSphereStopsNearTheLimitLoad) {
  const HillSphere h;
  TempDir dir("hill-sphere-limit");
  write_file(dir / "sphere.geo", sphere_octant_geo(h.a, h.b, n_arc, n_rad));
  // Ramp to 1.1 p_L, finely around p_L.
  auto r = run_stepped(
      dir.path(), sphere_case(h, h.limit(),
                              "times: [0.6, 0.8, 0.9, 0.95, 0.98, 0.99, 1.0, 1.01, 1.02, 1.03, "
                              "1.05, 1.1]"));
  EXPECT_EQ(r->result.status, AnalysisStatus::not_converged);
  ASSERT_FALSE(r->all.reports.empty());
  const double p_last = h.limit() * r->all.reports.back().time;
  report(fmt::format("sphere limit: last converged p/pL {:.4f} after {} steps ({:.1f} s); {}",
                     p_last / h.limit(), r->all.reports.size(), r->seconds, r->result.failure));
  // The run must stop: beyond the limit load no equilibrium exists, and (with the default
  // solver.mechanism_limit) a step that "converges" with displacements of 5 % of the model's
  // size is refused as a mechanism. The last converged step is checked against both sides:
  // - Lower bound 0.99 p_L. The mesh's displacement fields are kinematically admissible, so
  //   its limit load is, by the upper-bound theorem, not below p_L (up to the quadrature of the
  //   dissipation): every step below p_L has an equilibrium and must converge. The step at
  //   exactly p_L may still fail (the tangent is singular there), hence the step before it.
  // - Upper bound 1.03 p_L. How far above p_L the discrete limit load lies is the error with
  //   which the mesh represents the collapse mechanism, the purely radial isochoric flow
  //   u ∝ 1/r² through the whole wall: the quadratic elements interpolate it to O((h_r/a)²)
  //   = 1.6 % in energy, and the full 27-point integration of an incompressible flow stiffens
  //   it a little more (as for the hex20 cylinder of test_verify_plastic.cpp): 3 %.
  EXPECT_GE(p_last, 0.99 * h.limit());
  EXPECT_LE(p_last, 1.03 * h.limit());
}

}  // namespace
}  // namespace hencky::verify
