// Solver-level verification of frictionless contact with rigid surfaces (docs/contact.md): whole
// analyses compared with closed forms, with each other, and with the balance of forces.
//
// 1. Hertz (VerifyContactHertz). A rigid sphere, radius R, pressed by a prescribed approach δ
//    (its `motion`, two steps) into a quarter of an elastic block (x, y ≥ 0, symmetry rollers
//    on x = 0 and y = 0, bottom held), 10-node tetrahedra from a .geo whose size field is h_c
//    within 1.1 a of the contact point, growing by 0.25 per unit distance outside. Hertz for a
//    rigid indenter on an elastic half-space, E* = E/(1 − ν²): P = (4/3)E*√R δ^{3/2},
//    a = √(Rδ), p0 = 3P/(2πa²), p(r) = p0√(1 − r²/a²). Compared: the force P (contact
//    resultant, four quarters), the contact radius a and peak pressure p0 (estimator below),
//    the approach δ(P) that Hertz gives for the measured P, and the whole pressure field (L2
//    over the contact region, tributary-area weights), on h_c = a/3 and a/8.
//
//    The model differs from Hertz's half-space in two ways that do not depend on the mesh, and
//    both make the block stiffer. (i) Its finite size: the block is L = 200a (bottom held at
//    depth L, sides free); measured at h_c = a/8 and a/R = 0.02, P exceeds Hertz by +2.01, +1.15,
//    +0.71, +0.52 % for L = 50a, 100a, 200a, 400a, i.e. by ≈ 0.9 a/L, +0.44 % here. (ii) A
//    finite a/R: the gap is measured to the true sphere from the displaced nodes, whose radial
//    displacement u_r (∝ (1 − 2ν)) Hertz neglects; this adds ≈ +0.18 % per 0.01 of a/R (+0.27 %
//    going from a/R = 0.02 to 0.005 at L = 200a). With a/R = 0.01 the two add up to ≈ +0.6 % on
//    P (+0.4 % on δ(P)). The mesh error of P is smaller than that and of the other sign (a
//    coarse mesh resolves the edge of the contact late and carries less force): P is +0.35 %
//    from Hertz at h_c = a/3 and +0.54 % at a/8 (−0.3 % at a/2 with a/R = 0.02), so its error
//    vs Hertz cannot decrease under refinement; it is checked against the 5 % bound only. The
//    quantities whose error is the mesh's — a, p0 and the pressure field — must be within 5 % on
//    the finer mesh and better on it than on the coarser one.
//
//    Estimator of a and p0. The nodal pressure is the support's normal force over the node's
//    tributary area ∫Ñ dA (nodal_contact). Hertz's p² = p0²(1 − r²/a²) is linear in r², so a
//    least-squares line p² = A + B r² through the nodes in contact gives p0 = √A and
//    a = √(−A/B) from the whole interior of the contact rather than from one node. The nodes
//    near the edge of the contact are left out (r > 0.8 r_max, r_max the largest radius of a
//    node in contact: the measured extent, not Hertz's a): their tributary patches straddle the
//    edge, so their pressure is an average over a region where p falls to zero. Also printed:
//    a from P and p0, √(3P/(2π p0)).
//
// 2. The same indentation with the sphere as an STL icosphere (VerifyContactStl), on one mesh,
//    against the analytic sphere on the same mesh: their difference is the facets' only. The
//    icosphere's vertices are on the sphere, so the polyhedron lies inside the ball of radius R
//    and contains the concentric ball of radius R − s, s the largest sagitta (R minus the
//    distance of a facet's plane from the centre). Its indentation lies between the analytic
//    one (δ, R) and that of the inner ball: approach δ − s, radius R − s. With Hertz's scaling,
//    P ∝ R^{1/2}δ^{3/2} and p0 ∝ (δ/R)^{1/2}, hence
//        0 ≤ 1 − P_stl/P_sphere ≤ 1 − (1 − s/R)^{1/2}(1 − s/δ)^{3/2}      (≈ 1.5 s/δ),
//        |1 − p0_stl/p0_sphere| ≤ 1 − ((1 − s/δ)/(1 − s/R))^{1/2}          (≈ 0.5 s/δ),
//    plus what the two runs may leave unconverged (their gaps within the allowed penetration,
//    3 g_allowed/δ on P). The p0 bound is taken two-sided: the fitted p0 also carries the
//    facet-scale ripple of the nodal pressures (facet edges ≈ mesh size). Measured (k = 5 and 6
//    subdivisions; the test uses k = 5): P −2.62 % and −0.68 % for s/δ = 2.85 % and 0.71 %,
//    i.e. ∝ s, 0.61 of the bound; the pressure fields differ by 8.4 % and 2.3 % (L2), also ∝ s.
//
// 3. A rigid cylinder (axis along y) pressed into an elastoplastic slab (linear hardening) in
//    plane strain (VerifyContactPlastic): one layer of tetrahedra (tet10) between rollers on
//    both y faces, half model (x ≥ 0). Two elastic steps, one long plastic step to δ_max =
//    3.4 δ_yield, two elastic unloading steps to δ_max/2, with `newton` and with
//    `initial-stress-stiffness`. The schemes solve the same discrete problem at
//    every step (docs/schemes.md: both take the flow direction of the iterate's trial stress;
//    the load path was chosen, when the fixed-matrix schemes kept the direction of the step's
//    start, so that each plastic step starts from a state without plastic flow: checked, no
//    plastic points in the elastic and unloading steps). Then
//    the curves differ only by what the iterations leave: by the argument of
//    test_verify_plastic_schemes.cpp a relative residual ≤ tol leaves a relative error
//    ≤ (1 + 3G/H) tol, twice for the curve defect, in each of the two runs: 4(1 + 3G/H) tol of
//    the force scale; plus the contact's stopping rule: every node in contact is within the
//    allowed gap g_a of the surface, so each run's force lies between those of approaches δ ± g_a:
//    2 k g_a, with k the slope of the force-indentation curve (bounded by twice its largest
//    secant between recorded points: the elastic plane-strain curve is slightly convex,
//    P ∝ δ^{1.1}). (newton's extrapolating predictor is off with contact: it pushed this long
//    plastic step's contact nodes deep into the cylinder, and the step was cut back three
//    times.)
//
// 4. A block whose bottom face starts a gap g above a rigid plane that rises through it within a
//    step (VerifyContactClosingGap): free until the plane arrives, then uniform uniaxial
//    compression, exact in the element space.
//
// Tests 1 and 3 also check the balance of forces: the reaction of the held bottom and the
// support's resultant cancel up to the residual the solver leaves (Cauchy–Schwarz over the free
// unknowns: √n_free · tol · ‖F_int‖).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "contact/contact.hpp"
#include "output/results.hpp"
#include "stl_support.hpp"
#include "verify_support.hpp"

namespace hencky {
namespace {

using verify::num;
using verify::report;
namespace fs = std::filesystem;
constexpr double pi = std::numbers::pi;

constexpr double E = 200e9, nu = 0.3;
constexpr double E_star = E / (1 - nu * nu);

/// What the log of a run says about its contact iterations.
struct LogStats {
  int kappa_raised = 0;  ///< iterations in which some node's κ was raised
  int cutbacks = 0;
};
LogStats log_stats(const Log& log) {
  LogStats s;
  for (const std::string& line : log.lines()) {
    if (line.find("κ raised") != std::string::npos) ++s.kappa_raised;
    if (line.find("cutting back") != std::string::npos) ++s.cutbacks;
  }
  return s;
}

std::string run_summary(const verify::SteppedRun& r) {
  std::string its;
  for (const StepReport& rep : r.all.reports) its += fmt::format("{}{}", its.empty() ? "" : " ", rep.iterations);
  const LogStats ls = log_stats(r.log);
  return fmt::format("{} dofs, {:.1f} s, iterations per step {}, {} factorizations, κ raised in "
                     "{} iterations, {} cut-backs",
                     r.model().dofs().n_dofs(), r.seconds, its, r.result.factorizations,
                     ls.kappa_raised, ls.cutbacks);
}

/// What a relative residual ≤ tol (force scale ≥ ‖F_int‖) allows for the sum of the residual's
/// components over the free unknowns, hence for |reaction + support resultant|: √n_free·tol·‖F_int‖.
double balance_bound(const Model& model, const State& s, double tol) {
  double f2 = 0;
  for (int i = 0; i < model.dofs().n_dofs(); ++i)
    if (model.dofs().eq[i] >= 0) f2 += s.f_int[i] * s.f_int[i];
  return std::sqrt(static_cast<double>(model.dofs().n_free)) * tol * std::sqrt(f2);
}

/// The largest allowed gap (penetration times the local element size) of the points that are in
/// contact in some state of `states`: how far the stopping rule lets a pressed node be from the
/// surface.
double largest_allowed_gap(const Model& model, const std::vector<State>& states) {
  const ContactBody& body = model.contacts()[0];
  double g = 0;
  for (const State& s : states)
    for (int i = 0; i < static_cast<int>(body.points.size()); ++i)
      if (s.contact[0][i].contact) g = std::max(g, body.allowed_gap(i));
  return g;
}

// ------------------------------------------------------------------------------------------
// Hertz

/// A quarter block [0, L] x [0, L] x [−L, 0] for Gmsh (built-in kernel), meshed with a size
/// field that is h_c within the distance r_fine of the origin (where the indenter touches) and
/// grows by `growth` per unit distance beyond, up to h_max. Regions: body; xsym (x = 0), ysym
/// (y = 0), top (z = 0), bottom (z = −L); the faces x = L and y = L have none.
std::string graded_quarter_block_geo(double L, double h_c, double r_fine, double growth,
                                     double h_max) {
  return verify::box_entities_geo(Vec3(0, 0, -L), Vec3(L, L, 0), h_max) +
         fmt::format(R"geo(Physical Volume("body") = {{1}};
Physical Surface("xsym") = {{6}}; Physical Surface("ysym") = {{3}};
Physical Surface("top") = {{2}}; Physical Surface("bottom") = {{1}};
Field[1] = MathEval;
Field[1].F = "min({}, {} + {}*max(0, sqrt(x*x + y*y + z*z) - {}))";
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0; Mesh.MeshSizeFromPoints = 0; Mesh.MeshSizeFromCurvature = 0;
)geo",
                     num(h_max), num(h_c), num(growth), num(r_fine));
}

/// Hertz: a rigid sphere of radius R pressed by δ into an elastic half-space (E*).
struct Hertz {
  double R;
  double force(double d) const { return 4.0 / 3.0 * E_star * std::sqrt(R) * std::pow(d, 1.5); }
  double radius(double d) const { return std::sqrt(R * d); }
  double peak(double d) const { return 3 * force(d) / (2 * pi * R * d); }
  double approach(double P) const {
    return std::pow(3 * P / (4 * E_star * std::sqrt(R)), 2.0 / 3.0);
  }
};

/// p0 and a of a contact centred on the z axis, by the least-squares fit of p² = A + B r² over
/// the nodes in contact with r ≤ r_cut (default 0.8 r_max; see the header).
struct PressureFit {
  double p0 = 0, a = 0;
  double r_max = 0;  ///< largest radius of a node in contact
  int used = 0;      ///< nodes in the fit
};

PressureFit fit_hertz_pressure(const Model& model, const State& state, double r_cut = 0) {
  const NodalContact nc = nodal_contact(model, state);
  const ContactBody& b = model.contacts()[0];
  PressureFit f;
  std::vector<std::pair<double, double>> rp;  // (r², p)
  for (std::size_t i = 0; i < b.points.size(); ++i) {
    if (!state.contact[0][i].contact) continue;
    const Vec3& x = b.points[i].x;
    const double r = std::hypot(x.x(), x.y());
    f.r_max = std::max(f.r_max, r);
    rp.emplace_back(r * r, nc.pressure[b.points[i].node]);
  }
  if (r_cut <= 0) r_cut = 0.8 * f.r_max;
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (auto [r2, p] : rp) {
    if (r2 > r_cut * r_cut) continue;
    n += 1;
    sx += r2;
    sy += p * p;
    sxx += r2 * r2;
    sxy += r2 * p * p;
  }
  f.used = static_cast<int>(n);
  const double B = (n * sxy - sx * sy) / (n * sxx - sx * sx), A = (sy - B * sx) / n;
  f.p0 = std::sqrt(A);
  f.a = std::sqrt(-A / B);
  return f;
}

/// Relative L2 difference, weighted by the tributary areas, of the nodal contact pressures from
/// p(r) = p0 √(1 − r²/a²) over all the points of the contact region (a point outside the
/// contact carries p = 0 on both sides).
double pressure_field_error(const Model& model, const State& state, double p0, double a) {
  const NodalContact nc = nodal_contact(model, state);
  double e2 = 0, p2 = 0;
  for (const ContactPoint& p : model.contacts()[0].points) {
    const double r = std::hypot(p.x.x(), p.x.y());
    const double ph = r < a ? p0 * std::sqrt(1 - r * r / (a * a)) : 0.0;
    e2 += p.area * (nc.pressure[p.node] - ph) * (nc.pressure[p.node] - ph);
    p2 += p.area * ph * ph;
  }
  return std::sqrt(e2 / p2);
}

struct IndentationFigures {
  double delta = 0;     ///< the indenter's prescribed approach
  double P = 0;         ///< vertical force of the full model (four quarters)
  PressureFit fit;
  double a_from_P = 0;  ///< √(3P / (2π p0))
  double balance = 0;   ///< |reaction(bottom).z + resultant.z|
  double balance_bound = 0;
  int nodes = 0;
};

struct IndentationRun {
  std::unique_ptr<verify::SteppedRun> run;
  std::vector<IndentationFigures> steps;
  const State& last() const { return run->all.states.back(); }
};

/// The quarter block of `geo` pressed by a rigid indenter `surface` (contact[0].surface) moving
/// down by δ(t) = delta·t; the figures of every converged step.
IndentationRun indent(const fs::path& dir, const std::string& geo, const std::string& surface,
                      double delta, const std::string& times, double penetration,
                      double tolerance) {
  verify::write_file(dir / "block.geo", geo);
  const std::string yaml = fmt::format(R"yaml(mesh: {{file: block.geo, order: 2}}
materials:
  - {{E: {}, nu: {}}}
boundary:
  - {{region: xsym, displacement: {{x: 0}}}}
  - {{region: ysym, displacement: {{y: 0}}}}
  - {{region: bottom, displacement: {{x: 0, y: 0, z: 0}}}}
contact:
  - name: ball
    nodes: top
    surface: {}
    motion: [0, 0, "-{}*t"]
    penetration: {}
solver: {{times: [{}], tolerance: {}}}
output: {{reactions: [bottom]}}
)yaml",
                                       num(E), num(nu), surface, num(delta), num(penetration),
                                       times, num(tolerance));
  IndentationRun out;
  out.run = verify::run_stepped(dir, yaml);
  const auto& r = *out.run;
  for (const State& s : r.all.states) {
    IndentationFigures f;
    f.delta = delta * s.time;
    const ContactTotals t = contact_totals(r.model(), s)[0];
    f.P = -4 * t.resultant.z();
    f.nodes = t.nodes;
    f.fit = fit_hertz_pressure(r.model(), s);
    f.a_from_P = std::sqrt(3 * f.P / (2 * pi * f.fit.p0));
    f.balance = std::abs(region_reactions(r.model(), s)[0].z() + t.resultant.z());
    f.balance_bound = balance_bound(r.model(), s, tolerance);
    out.steps.push_back(f);
  }
  return out;
}

std::string sphere_yaml(double R) {
  return fmt::format("{{sphere: {{center: [0, 0, {}], radius: {}}}}}", num(R), num(R));
}

TEST(VerifyContactHertz, RigidSphereOnAnElasticHalfSpace) {
  const double a = 1e-3, R = 100 * a, delta = a * a / R, L = 200 * a, tol = 1e-6;
  const Hertz hz{R};
  struct Errors {
    double P, a, p0, delta, field;
  };
  std::vector<Errors> errors;  // at the last step, coarse then fine
  for (int n : {3, 8}) {
    verify::TempDir dir("contact-hertz");
    const IndentationRun run =
        indent(dir.path(), graded_quarter_block_geo(L, a / n, 1.1 * a, 0.25, L / 4),
               sphere_yaml(R), delta, "0.5, 1", 1e-4, tol);
    ASSERT_EQ(run.run->result.status, AnalysisStatus::converged) << run.run->result.failure;
    ASSERT_EQ(run.steps.size(), 2u);
    for (std::size_t k = 0; k < run.steps.size(); ++k) {
      const IndentationFigures& f = run.steps[k];
      const Errors e{f.P / hz.force(f.delta) - 1, f.fit.a / hz.radius(f.delta) - 1,
                     f.fit.p0 / hz.peak(f.delta) - 1, hz.approach(f.P) / f.delta - 1,
                     pressure_field_error(run.run->model(), run.run->all.states[k],
                                          hz.peak(f.delta), hz.radius(f.delta))};
      report(fmt::format(
          "hertz h = a/{}, δ = {:.3g} (a = {:.3g}, a/R = {:.3g}): P {:+.2f} %, a {:+.2f} % (from "
          "P and p0 {:+.2f} %), p0 {:+.2f} %, δ(P) {:+.2f} %, pressure field {:.2f} % (L2); {} "
          "nodes in contact, {} in the fit; |R_bottom + F_contact| = {:.1e} P (bound {:.1e})",
          n, f.delta, hz.radius(f.delta), hz.radius(f.delta) / R, 100 * e.P, 100 * e.a,
          100 * (f.a_from_P / hz.radius(f.delta) - 1), 100 * e.p0, 100 * e.delta, 100 * e.field,
          f.nodes, f.fit.used, 4 * f.balance / f.P, 4 * f.balance_bound / f.P));
      EXPECT_LT(f.balance, f.balance_bound) << "h = a/" << n << ", t = " << run.run->all.states[k].time;
      if (k + 1 == run.steps.size()) errors.push_back(e);
    }
    report(fmt::format("hertz h = a/{}: {}", n, run_summary(*run.run)));
  }
  const Errors &coarse = errors[0], &fine = errors[1];
  EXPECT_LT(std::abs(fine.P), 0.05);
  EXPECT_LT(std::abs(fine.delta), 0.05);
  EXPECT_LT(std::abs(fine.a), 0.05);
  EXPECT_LT(std::abs(fine.p0), 0.05);
  EXPECT_LT(fine.field, 0.05);
  EXPECT_LT(std::abs(fine.a), std::abs(coarse.a));
  EXPECT_LT(std::abs(fine.p0), std::abs(coarse.p0));
  EXPECT_LT(fine.field, coarse.field);
}

// ------------------------------------------------------------------------------------------
// The rigid sphere as an STL surface

TEST(VerifyContactStl, IcosphereIndentsLikeTheAnalyticSphere) {
  const double a = 1e-3, R = 10 * a, delta = a * a / R, L = 50 * a;
  const double penetration = 1e-4, tol = 1e-6;
  const int k = 5;  // 20480 triangles, edges ≈ 0.33 a, about the mesh size a/4
  const Vec3 center(0, 0, R);
  verify::TempDir dir("contact-stl");
  const std::string geo = graded_quarter_block_geo(L, a / 4, 1.1 * a, 0.25, L / 4);
  write_icosphere_stl(dir / "ball.stl", center, R, k, true);
  double s = 0;  // the largest sagitta
  for (const StlTriangle& t : icosphere_triangles(center, R, k)) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
    s = std::max(s, R - std::abs(n.dot(t[0] - center)));
  }
  const IndentationRun sph = indent(dir.path(), geo, sphere_yaml(R), delta, "0.5, 1", penetration, tol);
  ASSERT_EQ(sph.run->result.status, AnalysisStatus::converged) << sph.run->result.failure;
  const IndentationRun stl =
      indent(dir.path(), geo, "{mesh: {file: ball.stl}}", delta, "0.5, 1", penetration, tol);
  ASSERT_EQ(stl.run->result.status, AnalysisStatus::converged) << stl.run->result.failure;

  const IndentationFigures& fs = sph.steps.back();
  // The STL run's p0 from the same nodes as the sphere's (r ≤ 0.8 r_max of the sphere run).
  const PressureFit fit = fit_hertz_pressure(stl.run->model(), stl.last(), 0.8 * fs.fit.r_max);
  const double P_stl = stl.steps.back().P;
  const NodalContact p_sph = nodal_contact(sph.run->model(), sph.last()),
                     p_stl = nodal_contact(stl.run->model(), stl.last());
  double d2 = 0, p2 = 0, dmax = 0;
  for (const ContactPoint& p : sph.run->model().contacts()[0].points) {
    const double d = p_stl.pressure[p.node] - p_sph.pressure[p.node];
    d2 += p.area * d * d;
    p2 += p.area * p_sph.pressure[p.node] * p_sph.pressure[p.node];
    dmax = std::max(dmax, std::abs(d));
  }
  const double g_allowed =
      std::max(largest_allowed_gap(sph.run->model(), {sph.last()}),
               largest_allowed_gap(stl.run->model(), {stl.last()}));
  const double slack = 3 * g_allowed / delta;
  const double bound_P = 1 - std::sqrt(1 - s / R) * std::pow(1 - s / delta, 1.5) + slack;
  const double bound_p0 = 1 - std::sqrt((1 - s / delta) / (1 - s / R)) + slack;
  const double dP = 1 - P_stl / fs.P, dp0 = 1 - fit.p0 / fs.fit.p0;
  report(fmt::format(
      "stl sphere ({} triangles), largest sagitta {:.3g} = {:.3g} δ: P {:+.3f} % (bound −{:.3f} "
      "%), p0 {:+.3f} % (bound ±{:.3f} %), a {:+.3f} %; pressure field {:.2f} % (L2), largest "
      "nodal difference {:.2f} % of p0; nodes in contact {} (sphere {})",
      20 << (2 * k), s, s / delta, -100 * dP, 100 * bound_P, -100 * dp0, 100 * bound_p0,
      100 * (fit.a / fs.fit.a - 1), 100 * std::sqrt(d2 / p2), 100 * dmax / fs.fit.p0,
      stl.steps.back().nodes, fs.nodes));
  report("stl sphere, analytic surface: " + run_summary(*sph.run));
  report("stl sphere, STL surface:      " + run_summary(*stl.run));
  EXPECT_GE(dP, -slack);  // the polyhedron is inside the ball: never more force
  EXPECT_LE(dP, bound_P);
  EXPECT_LE(std::abs(dp0), bound_p0);
}

// ------------------------------------------------------------------------------------------
// Rigid cylinder pressed into an elastoplastic slab (plane strain), two schemes

/// A slab [0, W] x [0, t] x [−D, 0]: a 2D mesh of the x-z section, graded from h_c within
/// r_fine of the origin by `growth` per unit distance up to h_max, extruded by one layer of
/// tetrahedra through the thickness t. Regions: body; xsym (x = 0), front (y = 0), back (y = t),
/// top (z = 0), bottom (z = −D).
std::string graded_slab_geo(double W, double D, double t, double h_c, double r_fine,
                            double growth, double h_max) {
  return fmt::format(R"geo(W = {}; D = {}; t = {};
Point(1) = {{0, 0, 0}}; Point(2) = {{W, 0, 0}}; Point(3) = {{W, 0, -D}}; Point(4) = {{0, 0, -D}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
Field[1] = MathEval;
Field[1].F = "min({}, {} + {}*max(0, sqrt(x*x + z*z) - {}))";
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0; Mesh.MeshSizeFromPoints = 0; Mesh.MeshSizeFromCurvature = 0;
out[] = Extrude {{0, t, 0}} {{ Surface{{1}}; Layers{{1}}; }};
Physical Volume("body") = {{out[1]}};
Physical Surface("front") = {{1}};
Physical Surface("back") = {{out[0]}};
Physical Surface("top") = {{out[2]}};
Physical Surface("bottom") = {{out[4]}};
Physical Surface("xsym") = {{out[5]}};
)geo",
                     num(W), num(D), num(t), num(h_max), num(h_c), num(growth), num(r_fine));
}

TEST(VerifyContactPlastic, CylinderIntoAnElastoplasticSlabTwoSchemesAgree) {
  // R = 10 mm; a = 81 µm is the half-width the elastic solution would have at δ_max (p0 = 3.6
  // σ_y); first yield at δ ≈ 4.4e-7 (p0 ≈ 1.8 σ_y).
  const double R = 0.01, a = 8.1e-5, h = a / 6, d_max = 1.5e-6;
  const double sy = 250e6, H = 20e9, tol = 1e-8, penetration = 1e-8;
  const double G = E / (2 * (1 + nu));
  const std::vector<double> times{0.1, 0.2, 1.0, 1.25, 1.5};
  const std::vector<bool> plastic_step{false, false, true, false, false};
  auto indentation = [&](double t) { return d_max * (t <= 1 ? t : 2 - t); };
  verify::TempDir dir("contact-cylinder");
  verify::write_file(dir / "slab.geo", graded_slab_geo(40 * a, 40 * a, h, h, 2 * a, 0.3, 8 * a));

  struct Variant {
    std::string label, scheme, options;
  };
  const Variant variants[] = {{"newton", "newton", ""},
                              {"initial-stress-stiffness", "initial-stress-stiffness", ""}};
  struct Curve {
    std::vector<double> time, P;
    double g_allowed = 0;
  };
  std::vector<Curve> curves;
  for (const Variant& v : variants) {
    const std::string yaml = fmt::format(R"yaml(mesh: {{file: slab.geo, order: 2}}
materials:
  - E: {}
    nu: {}
    plasticity: {{linear: {{yield: {}, hardening: {}}}}}
boundary:
  - {{region: xsym, displacement: {{x: 0}}}}
  - {{region: front, displacement: {{y: 0}}}}
  - {{region: back, displacement: {{y: 0}}}}
  - {{region: bottom, displacement: {{x: 0, y: 0, z: 0}}}}
contact:
  - name: roller
    nodes: top
    surface: {{cylinder: {{point: [0, 0, {}], axis: [0, 1, 0], radius: {}}}}}
    motion: [0, 0, "-{}*(t <= 1 ? t : 2 - t)"]
    penetration: {}
solver: {{scheme: {}, {}times: [{}], tolerance: {}, max_iterations: 400}}
output: {{reactions: [bottom]}}
)yaml",
                                         num(E), num(nu), num(sy), num(H), num(R), num(R),
                                         num(d_max), num(penetration), v.scheme, v.options,
                                         fmt::join(times, ", "), num(tol));
    const auto run = verify::run_stepped(dir.path(), yaml, fmt::format("case{}.yaml", curves.size()));
    ASSERT_EQ(run->result.status, AnalysisStatus::converged) << v.label << ": " << run->result.failure;
    Curve c;
    std::string line;
    int plastic = 0;
    for (std::size_t k = 0; k < run->all.states.size(); ++k) {
      const State& s = run->all.states[k];
      const StepReport& rep = run->all.reports[k];
      const ContactTotals tot = contact_totals(run->model(), s)[0];
      c.time.push_back(s.time);
      c.P.push_back(-tot.resultant.z());
      plastic = std::max(plastic, rep.plastic_points);
      line += fmt::format("\n    δ = {:.3g}: P = {:.7g} N ({} nodes), {} plastic points, {} iterations",
                          indentation(s.time), c.P.back(), tot.nodes, rep.plastic_points,
                          rep.iterations);
      EXPECT_LT(std::abs(region_reactions(run->model(), s)[0].z() + tot.resultant.z()),
                balance_bound(run->model(), s, tol))
          << v.label << ", t = " << s.time;
    }
    c.g_allowed = largest_allowed_gap(run->model(), run->all.states);
    report(fmt::format("cylinder, {}: {}{}", v.label, run_summary(*run), line));
    EXPECT_GT(plastic, 0) << v.label << ": no plastic zone";
    double eps_p = 0;
    for (double e : run->all.states.back().eps_p_eq) eps_p = std::max(eps_p, e);
    EXPECT_GT(eps_p, 0) << v.label;
    ASSERT_EQ(c.time, times) << v.label;  // the planned steps, no cut-back
    for (std::size_t k = 0; k < times.size(); ++k) {
      if (plastic_step[k]) {
        EXPECT_GT(run->all.reports[k].plastic_points, 0) << v.label << ", t = " << times[k];
      } else {
        EXPECT_EQ(run->all.reports[k].plastic_points, 0) << v.label << ", t = " << times[k];
      }
    }
    curves.push_back(std::move(c));
  }

  const Curve &a_run = curves[0], &b_run = curves[1];
  double p_max = 0, k_secant = 0, diff = 0;
  for (const Curve* c : {&a_run, &b_run})
    for (std::size_t k = 0; k < c->P.size(); ++k) {
      p_max = std::max(p_max, c->P[k]);
      const double dd = indentation(c->time[k]) - (k ? indentation(c->time[k - 1]) : 0.0);
      k_secant = std::max(k_secant, std::abs((c->P[k] - (k ? c->P[k - 1] : 0.0)) / dd));
    }
  for (std::size_t k = 0; k < times.size(); ++k) diff = std::max(diff, std::abs(a_run.P[k] - b_run.P[k]));
  const double bound = 4 * (1 + 3 * G / H) * tol * p_max +
                       2 * (2 * k_secant) * std::max(a_run.g_allowed, b_run.g_allowed);
  report(fmt::format(
      "cylinder: newton and initial-stress-stiffness differ by at most {:.2e} of the largest "
      "force (bound {:.2e}: iterations {:.2e}, gaps {:.2e})",
      diff / p_max, bound / p_max, 4 * (1 + 3 * G / H) * tol,
      4 * k_secant * std::max(a_run.g_allowed, b_run.g_allowed) / p_max));
  EXPECT_LE(diff, bound);
}

// ------------------------------------------------------------------------------------------
// A gap closed by a moving plane within a step

TEST(VerifyContactClosingGap, APlaneRisingThroughTheGapCompressesTheBlockExactly) {
  // The unstructured tet10 cube [0, 1]^3 on rollers (x0, y0), its top z1 held; its bottom z0
  // starts g above the plane z = −g, which rises by 3g·t: it reaches the block at t = 1/3,
  // inside the second step, then compresses it uniformly: σ_zz = −E(3g t − g) (uniaxial).
  const double g = 1e-3;
  verify::TempDir dir("contact-gap");
  verify::write_file(dir / "box.geo", verify::box_geo(1, 1, 1, 0.5));
  const std::string yaml = verify::block_on_plane_case(
      "{file: box.geo, order: 2}", -g, num(3 * g) + "*t", "0.25, 0.5, 0.75, 1", E, nu);
  const auto run = verify::run_stepped(dir.path(), yaml);
  ASSERT_EQ(run->result.status, AnalysisStatus::converged) << run->result.failure;
  ASSERT_EQ(run->all.states.size(), 4u);
  const int n_points = static_cast<int>(run->model().contacts()[0].points.size());
  const double scale = E * 2 * g;  // |σ_zz| at t = 1
  for (const State& s : run->all.states) {
    const double szz = -E * std::max(0.0, 3 * g * s.time - g) + 0.0;
    double worst = 0;
    for (const Voigt& sig : s.stress) {
      worst = std::max(worst, std::abs(sig[2] - szz));
      for (int c : {0, 1, 3, 4, 5}) worst = std::max(worst, std::abs(sig[c]));
    }
    const ContactTotals tot = contact_totals(run->model(), s)[0];
    const Vec3 reaction = region_reactions(run->model(), s)[0];
    report(fmt::format("closing gap, t = {:g}: {} of {} nodes in contact, σ_zz = {:.6g} expected, "
                       "largest stress error {:.2e} of E·2g; support {:.6g}, reaction {:.6g}",
                       s.time, tot.nodes, n_points, szz, worst / scale, tot.resultant.z(),
                       reaction.z()));
    EXPECT_LT(worst, 1e-9 * scale) << "t = " << s.time;
    EXPECT_EQ(tot.nodes, s.time < 1.0 / 3 ? 0 : n_points) << "t = " << s.time;
    EXPECT_NEAR(tot.resultant.z(), -szz, 1e-9 * scale) << "t = " << s.time;
    EXPECT_NEAR(reaction.z() + tot.resultant.z(), 0, 1e-9 * scale) << "t = " << s.time;
    if (s.time < 1.0 / 3) {  // still open: every node at the plane's distance
      const NodalContact nc = nodal_contact(run->model(), s);
      for (const ContactPoint& p : run->model().contacts()[0].points)
        EXPECT_NEAR(nc.gap[p.node], g - 3 * g * s.time, 1e-12) << "node " << p.node;
    }
  }
  report("closing gap: " + run_summary(*run));
}

}  // namespace
}  // namespace hencky
