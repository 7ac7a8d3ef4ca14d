// Every iteration scheme against `newton` on structures: the thick cylinder of
// test_verify_plastic.cpp (plane-strain quarter ring) with linear hardening and with a
// Ramberg-Osgood curve, and a quarter of a plate with a central hole in tension (linear
// hardening), loaded into the elastic-plastic range.
//
// What "the same answer" means (docs/schemes.md, "One loop for all schemes"). Every scheme
// iterates towards the same converged point law: the stress projected on the step's flow
// direction Z lands on the curve. newton, variable-stiffness and the initial stresses take Z
// from the iterate's elastic trial stress, and for them that law is the radial return of
// `newton`; so do the initial strains for a point elastic at the start of the step, while for a
// point that was already flowing they keep the report's Z = Z(t) (explicit direction). Hence:
//
// (a) a plastic step that starts from a state without plastic flow (here: one elastic step,
//     then one step far into the plastic range) is the same discrete problem for every scheme,
//     and they differ from `newton` only by what the iterations leave unconverged;
// (b) over several plastic steps on a non-proportional path (the cylinder: σ_z drifts towards
//     the mean of σ_r and σ_θ as the wall yields) the same holds for the trial-direction
//     schemes, while the two initial-strain schemes share another discrete problem: they differ
//     from `newton` by O(Δt) (first order), and both tend to the same solution as the steps are
//     refined. This file checks both statements.
//
// The bound of (a). The step stops when the relative residual ‖F − F_int‖/‖F‖ and the scheme's
// curve defect (Δ^σ or Δ^ε, a relative RMS over the plastic points) are below solver.tolerance
// (tol). A residual r leaves a displacement error δu = K_t⁻¹r, where K_t is the consistent
// tangent of the converged state. For a radial return from an elastic state with hardening
// modulus H (dσ̃/dε̃^p), K_t ≥ H/(3G + H)·K_e as quadratic forms (the deviatoric stiffness is
// reduced at most to 2G·H/(3G + H) along the flow direction and to 2G·σ̃/σ̃_trial ≥ 2G·H/(3G + H)
// across it; the volumetric part stays elastic), and the secant stiffness of the solution is
// at most K_e. So the relative error is at most κ = 1 + 3G/H times the relative residual: the
// condition factor of the elastic-plastic problem (for a curve, H is its smallest slope in the
// plastic zone). The curve defect ≤ tol is a stress error of at most tol·σ̃, whose equivalent
// out-of-balance force is again ≤ tol relative, so it adds the same again; and both runs (the
// scheme's and newton's) carry such an error. Hence, for the relative difference of the
// displacement field and of ε̃^p (measured against ε̃^{e+p}, the strain scale of the curve),
//
//     |scheme − newton| ≤ 2 · 2 · κ · tol.
//
// This takes the relative residual as representative of the error in the norms compared: the
// whole displacement field, the displacements at the probes (relative to the largest
// displacement; the error is a smooth field) and ε̃^p as an RMS over the body. The largest
// pointwise ε̃^p difference gets the factor sqrt(V/V_plastic) on top: the iteration error
// lives in the plastic zone only (elastic points follow the linear law exactly), while the
// stopping measures are RMS values over the whole body (in the plate the zone is 0.8 % of the
// volume, the factor 11). The measured differences are well inside these bounds (the log
// prints them as multiples of tol: up to 1.3 tol for the norms, 24 tol for the pointwise ε̃^p
// in the plate). The tolerance-scaling check below confirms that the differences are iteration
// error: a scheme run at tol/100 comes 100 times closer to newton.
//
// What the schemes need here (every one converges, and each run asserts it):
// - variable-stiffness with curve_form: strain (2.34) at a strain-controlled point is the
//   fixed-point map σ̃ ← x·σ̃/F(σ̃), whose derivative at the solution is 1 − secant/tangent:
//   as the report writes it, it oscillates and diverges as soon as the secant is more than
//   twice the tangent, which is the case a little past first yield with H = E/10
//   (secant/tangent 4.5 at the hole edge of the plate) and everywhere for Ramberg-Osgood (the
//   ratio tends to n = 10). Under formulation: hencky a point whose secant alternates takes
//   the stress form for the rest of the step (schemes.cpp), and it converges.
// - initial-strain(-stiffness) needs relaxation: its iteration contracts by 1 − ω(1 + 3G/H)
//   at a strain-controlled plastic point (1 − ω(1 + E/H) under uniaxial stress), so ω must stay
//   below 2H/(3G + H) = 0.159 for H = E/10; ω = 0.1 is used. For Ramberg-Osgood the linear limit
//   at the bore (H ≈ 1.5e10) is about 0.12, but the first elastic iterate overshoots σ_y and
//   F ~ (σ̃/σ_y)^10 turns the relaxed correction into a divergence for ω = 0.1 (checked); ω =
//   0.05 converges.
#include <gtest/gtest.h>

#include <chrono>

#include "output/results.hpp"
#include "verify_support.hpp"

namespace hencky::verify {
namespace {

struct Scheme {
  std::string scheme, form = "stress";
  double omega = 1.0;
  bool converges = true;
  int max_iterations = 400;
  std::string acceleration = "auto";
  std::string label() const { return scheme + (form == "strain" ? " (strain)" : ""); }
};

struct SchemeRun {
  Scheme s;
  Log log;
  std::unique_ptr<InProcessRun> run;
  double seconds = 0;
  bool converged() const { return run->result.status == AnalysisStatus::converged; }
  const Model& model() const { return *run->loaded.model; }
  const State& state() const { return run->states.last; }
};

/// Writes the case given by `yaml(scheme)` into `dir` and runs it in-process (no files).
std::unique_ptr<SchemeRun> run_scheme(const fs::path& dir, const Scheme& s,
                                      const std::function<std::string(const Scheme&)>& yaml,
                                      const std::string& tag) {
  auto r = std::make_unique<SchemeRun>();
  r->s = s;
  r->log.quiet = true;
  const fs::path file = dir / fmt::format("{}-{}-{}.yaml", tag, s.scheme, s.form);
  write_file(file, yaml(s));
  const auto t0 = std::chrono::steady_clock::now();
  r->run = run_in_process(file, r->log);
  r->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

/// Volume of each integration point (its quadrature weight times the Jacobian).
std::vector<double> point_volumes(const Model& m) {
  std::vector<double> w(m.n_points());
  const auto& mesh = m.mesh();
  Vec3 x[max_cell_nodes];
  double dNdx[3 * max_cell_nodes];
  for (int c = 0; c < mesh.cells.size(); ++c) {
    const auto nodes = mesh.cells.nodes(c);
    const auto& tab = reference_table(mesh.cells.type[c]);
    for (std::size_t a = 0; a < nodes.size(); ++a) x[a] = mesh.x[nodes[a]];
    const std::span<const Vec3> xs(x, nodes.size());
    for (int q = 0; q < tab.n_points; ++q)
      w[m.point_offset(c) + q] = physical_gradients(tab, q, xs, dNdx) * tab.weights[q];
  }
  return w;
}

/// How far a state is from the reference (newton's) on the same mesh.
struct SchemeDifference {
  double u_field = 0;          ///< ‖u − u_ref‖ / ‖u_ref‖ over all nodes
  double u_probe = 0;          ///< max over the probes of |u − u_ref| / max nodal |u_ref|
  double ep_max = 0;           ///< max over the points |ε̃^p − ε̃^p_ref| / max ε̃^{e+p}_ref
  double ep_rms = 0;           ///< volume RMS of ε̃^p − ε̃^p_ref / that of ε̃^{e+p}_ref
  int zone = 0, zone_ref = 0;  ///< points with ε̃^p > 0
  int zone_mismatch = 0;       ///< plastic in one and not the other, with ε̃^p above the bound
  double zone_fraction = 0;    ///< volume of the reference's plastic points / total volume
  double ep_outside = 0;  ///< largest ε̃^p / max ε̃^{e+p}_ref of a point plastic in one only
  /// The factor from a volume RMS over the body to the plastic zone, where the iteration error
  /// lives (elastic points follow the linear law exactly): sqrt(V / V_plastic).
  double localization() const { return 1 / std::sqrt(zone_fraction); }
};

SchemeDifference difference(const Model& m, const State& s, const State& ref, double bound) {
  SchemeDifference d;
  double du2 = 0, u2 = 0, u_max = 0;
  for (std::size_t i = 0; i < ref.u.size(); ++i) {
    du2 += (s.u[i] - ref.u[i]) * (s.u[i] - ref.u[i]);
    u2 += ref.u[i] * ref.u[i];
  }
  for (std::size_t n = 0; n < ref.u.size() / 3; ++n)
    u_max = std::max(u_max, Vec3(ref.u[3 * n], ref.u[3 * n + 1], ref.u[3 * n + 2]).norm());
  d.u_field = std::sqrt(du2 / u2);
  const auto nodal = recover_nodal_stress(m, s), nodal_ref = recover_nodal_stress(m, ref);
  for (const Probe& p : m.probes()) {
    const Vec3 a = probe_values(m, p, s, nodal).displacement;
    const Vec3 b = probe_values(m, p, ref, nodal_ref).displacement;
    d.u_probe = std::max(d.u_probe, (a - b).norm() / u_max);
  }
  const auto w = point_volumes(m);
  double e_max = 0, de2 = 0, e2 = 0, v = 0, v_zone = 0;
  for (int p = 0; p < m.n_points(); ++p) e_max = std::max(e_max, ref.eps_ep[p]);
  for (int p = 0; p < m.n_points(); ++p) {
    const double a = s.eps_p_eq[p], b = ref.eps_p_eq[p];
    d.ep_max = std::max(d.ep_max, std::abs(a - b) / e_max);
    de2 += w[p] * (a - b) * (a - b);
    e2 += w[p] * ref.eps_ep[p] * ref.eps_ep[p];
    v += w[p];
    if (b > 0) v_zone += w[p];
    d.zone += a > 0;
    d.zone_ref += b > 0;
    if ((a > 0) != (b > 0)) {
      d.ep_outside = std::max(d.ep_outside, std::max(a, b) / e_max);
      if (std::max(a, b) > bound * e_max) ++d.zone_mismatch;
    }
  }
  d.ep_rms = std::sqrt(de2 / e2);
  d.zone_fraction = v_zone / v;
  return d;
}

/// The checks of the top of the file: the field norms (displacement, and ε̃^p as an RMS over
/// the body) and the probe displacements (relative to the largest displacement: a smooth
/// field) within `bound` = 4κ·tol; the largest pointwise ε̃^p difference within the bound
/// times the localization factor sqrt(V/V_plastic), since the iteration error lives in the
/// plastic zone only while the stopping measures are RMS values over the whole body; and the
/// same plastic zone, up to points whose plastic strain is below the bound.
void check_within(const SchemeDifference& d, double bound) {
  EXPECT_LE(d.u_field, bound);
  EXPECT_LE(d.u_probe, bound);
  EXPECT_LE(d.ep_rms, bound);
  EXPECT_LE(d.ep_max, bound * d.localization());
  EXPECT_EQ(d.zone_mismatch, 0);
  EXPECT_GT(d.zone_ref, 0) << "the case must reach the plastic range";
}

/// Runs every scheme of `schemes` (newton first), checks the expected convergence, compares the
/// converged ones with newton within 4·κ·tol (relative, see the top of the file; κ from newton's
/// run) and returns the runs. `tag` names the case in the log.
std::vector<std::unique_ptr<SchemeRun>> every_scheme(
    const fs::path& dir, const std::string& tag, const std::vector<Scheme>& schemes,
    const std::function<std::string(const Scheme&)>& yaml, double tol,
    const std::function<double(const SchemeRun&)>& kappa_of) {
  std::vector<std::unique_ptr<SchemeRun>> runs;
  for (const Scheme& s : schemes) runs.push_back(run_scheme(dir, s, yaml, tag));
  const SchemeRun& ref = *runs.front();
  EXPECT_EQ(ref.s.scheme, "newton");
  if (!ref.converged()) {
    ADD_FAILURE() << tag << ": newton did not converge: " << ref.run->result.failure;
    return runs;
  }
  const double kappa = kappa_of(ref), bound = 4 * kappa * tol;
  const double loc = difference(ref.model(), ref.state(), ref.state(), 0).localization();
  report(
      fmt::format("{}: kappa = 1 + 3G/H = {:.1f}, tol {:.0e}: bound 4 kappa tol = {:.2e} "
                  "({:.0f} tol); pointwise eps_p x sqrt(V/V_plastic) = {:.1f}",
                  tag, kappa, tol, bound, bound / tol, loc));
  for (const auto& r : runs) {
    SCOPED_TRACE(tag + ": " + r->s.label());
    EXPECT_EQ(r->converged(), r->s.converges) << r->run->result.failure;
    if (!r->converged()) {
      report(
          fmt::format("{}: {:<26} NOT CONVERGED ({} iterations, {} factorizations, {:.2f} s): "
                      "{}",
                      tag, r->s.label(), r->run->result.iterations, r->run->result.factorizations,
                      r->seconds, r->run->result.failure));
      continue;
    }
    const SchemeDifference d = difference(r->model(), r->state(), ref.state(), bound);
    report(fmt::format(
        "{}: {:<26} omega {:<4} iterations {:4d} factorizations {:3d} {:5.2f} s | vs newton "
        "(in tol): u field {:.2f} probes {:.2f} eps_p rms {:.2f} max {:.2f} | plastic points {} "
        "({} newton; {} more than the bound apart, largest eps_p of the others {:.1e} tol)",
        tag, r->s.label(), r->s.omega, r->run->result.iterations, r->run->result.factorizations,
        r->seconds, d.u_field / tol, d.u_probe / tol, d.ep_rms / tol, d.ep_max / tol, d.zone,
        d.zone_ref, d.zone_mismatch, d.ep_outside / tol));
    check_within(d, bound);
  }
  return runs;
}

double three_g(double E, double nu) {
  return 3 * E / (2 * (1 + nu));
}

// ------------------------------------------------------------------------------------------
// Thick cylinder a = 0.1, b = 0.2 under internal pressure, plane strain (the Hill cylinder of
// test_verify_plastic.cpp, 8 x 16 20-node hexahedra), with hardening. Limit pressure of the
// perfectly plastic cylinder p_L = 2 k ln(b/a), k = σ_y/√3; first yield at k(1 − a²/b²) =
// 0.54 p_L. Loaded to 0.8 p_L: the plastic zone reaches r ≈ 0.13, a third of the wall (Hill's
// perfectly plastic front is at 0.131).
struct HardeningCylinder {
  double a = 0.1, b = 0.2, E = 2e11, nu = 0.3, sy = 2.4e8;
  double limit() const { return 2 * sy / std::sqrt(3.0) * std::log(b / a); }
  std::string plasticity;  // the case's plasticity map
  std::string times;       // solver.times
  double tol = 1e-8;
  std::string yaml(const Scheme& s) const {
    return fmt::format(
        "mesh: {{file: ring.geo, order: 2}}\n"
        "materials:\n  - {{E: {}, nu: {}, plasticity: {}}}\n"
        "{}"
        "solver: {{scheme: {}, curve_form: {}, relaxation: {}, times: {}, tolerance: {}, "
        "max_iterations: {}, cutback: 0, acceleration: {}}}\n"
        "output:\n  probes:\n"
        "    - {{name: bore, point: [{}, 0, 0.0]}}\n"
        "    - {{name: bore45, point: [{}, {}, 0.0]}}\n"
        "    - {{name: mid, point: [{}, 0, 0.0]}}\n"
        "    - {{name: outer, point: [0, {}, 0.0]}}\n",
        num(E), num(nu), plasticity,
        ring_plane_strain_boundary("\"" + num(0.8 * limit()) + "*t\""), s.scheme, s.form, num(s.omega), times,
        num(tol), s.max_iterations, s.acceleration, num(a), num(a / std::sqrt(2.0)), num(a / std::sqrt(2.0)),
        num(0.5 * (a + b)), num(b));
  }
};

void write_ring(const TempDir& dir, const HardeningCylinder& c) {
  const int nr = 8;
  write_file(dir / "ring.geo", quarter_ring_geo(c.a, c.b, (c.b - c.a) / nr, nr, 2 * nr, "hex"));
}

/// The schemes with the relaxation and the expected outcome of a hardening curve whose
/// secant/tangent ratio exceeds 2 in the plastic zone (see the top of the file).
std::vector<Scheme> schemes_for(double omega_initial_strain) {
  return {
      {"newton"},
      {"variable-stiffness"},
      {"variable-stiffness", "strain"},
      {"initial-strain", "stress", omega_initial_strain},
      {"initial-strain-stiffness", "stress", omega_initial_strain},
      {"initial-stress"},
      {"initial-stress-stiffness"},
  };
}

// (a) Linear hardening H = E/10: one elastic step to 0.4 p_L, then one step to 0.8 p_L. The
// plastic step starts with no point flowing, so every scheme solves newton's equations.
TEST(VerifyPlasticSchemes, ThickCylinderLinearHardeningOnePlasticStep) {
  HardeningCylinder c;
  const double H = c.E / 10;
  c.plasticity = fmt::format("{{linear: {{yield: {}, hardening: {}}}}}", num(c.sy), num(H));
  c.times = "[0.5, 1]";
  TempDir dir("schemes-cylinder");
  write_ring(dir, c);
  const double kappa = 1 + three_g(c.E, c.nu) / H;
  auto yaml = [&](const Scheme& s) { return c.yaml(s); };
  auto runs = every_scheme(dir.path(), "cylinder linear", schemes_for(0.1), yaml, c.tol,
                           [&](const SchemeRun&) { return kappa; });
  ASSERT_TRUE(runs.front()->converged());

  // The differences are iteration error: the plain initial-stress iteration (the slowest to
  // converge, linearly; acceleration: none) at tol/100 comes at least 10 times closer to newton
  // (100 times in theory).
  const double bound = 4 * kappa * c.tol;
  const Scheme plain{"initial-stress", "stress", 1.0, true, 400, "none"};
  auto is = run_scheme(dir.path(), plain, yaml, "plain");
  ASSERT_TRUE(is->converged()) << is->run->result.failure;
  const SchemeDifference d1 = difference(is->model(), is->state(), runs.front()->state(), bound);
  HardeningCylinder tight = c;
  tight.tol = c.tol / 100;
  auto tight_yaml = [&](const Scheme& s) { return tight.yaml(s); };
  auto t = run_scheme(dir.path(), plain, tight_yaml, "tight");
  ASSERT_TRUE(t->converged()) << t->run->result.failure;
  const SchemeDifference d2 = difference(t->model(), t->state(), runs.front()->state(), bound);
  report(
      fmt::format("cylinder linear: initial-stress at tol/100: {} iterations; u field vs "
                  "newton {:.1e} -> {:.1e}, eps_p max {:.1e} -> {:.1e}",
                  t->run->result.iterations, d1.u_field, d2.u_field, d1.ep_max, d2.ep_max));
  EXPECT_LT(d2.u_field, d1.u_field / 10);
  EXPECT_LT(d2.ep_max, d1.ep_max / 10);
}

// The same with a Ramberg-Osgood curve (α = 0.002 E/σ_y, n = 10), loaded in one step to
// 0.8 p_L: every point flows from the first load on (the curve has no elastic range), and all
// of them start the step unstressed, so again every scheme solves newton's equations.
TEST(VerifyPlasticSchemes, ThickCylinderRambergOsgoodOneStep) {
  HardeningCylinder c;
  const double alpha = 0.002 * c.E / c.sy, n = 10;
  c.plasticity = fmt::format("{{ramberg_osgood: {{E: {}, yield: {}, alpha: {}, n: {}}}}}", num(c.E),
                             num(c.sy), num(alpha), num(n));
  c.times = "[1]";
  TempDir dir("schemes-cylinder-ro");
  write_ring(dir, c);
  // κ from the smallest plastic slope in the plastic zone: H = dσ̃/dε̃^p = σ̃/(n ε̃^p) falls
  // with the plastic strain, so it is smallest where ε̃^p is largest (the bore), in newton's
  // solution.
  auto kappa_of = [&](const SchemeRun& newton) {
    double ep_max = 0;
    for (double e : newton.state().eps_p_eq) ep_max = std::max(ep_max, e);
    const double s_at = c.sy * std::pow(ep_max * c.E / (alpha * c.sy), 1 / n);
    const double H_min = s_at / (n * ep_max);
    report(fmt::format("cylinder ramberg-osgood: largest eps_p {:.3e}, H there {:.3e}", ep_max,
                       H_min));
    return 1 + three_g(c.E, c.nu) / H_min;
  };
  auto yaml = [&](const Scheme& s) { return c.yaml(s); };
  every_scheme(dir.path(), "cylinder ramberg-osgood", schemes_for(0.05), yaml, c.tol, kappa_of);
}

// (b) Linear hardening over four plastic steps (0.5 p_L elastic, then to 0.8 p_L in steps of
// 0.075 p_L): points that flow in one step start the next one flowing, and the path is not
// proportional (σ_z drifts as the wall yields). Every scheme sees each iterate along the
// direction of its trial stress (scheme_law.hpp, `along_z`) and so solves newton's discrete
// problem: each agrees with newton within the bound of (a). With the report's explicit Z(t),
// which the initial strains kept before, they differed from newton by O(Δt): 2.8e-4 of the
// displacement field here, 1.2e-4 and 5.7e-5 with 8 and 16 steps.
TEST(VerifyPlasticSchemes, ThickCylinderSeveralStepsEverySchemeGivesNewtonsAnswer) {
  HardeningCylinder c;
  const double H = c.E / 10;
  c.plasticity = fmt::format("{{linear: {{yield: {}, hardening: {}}}}}", num(c.sy), num(H));
  TempDir dir("schemes-cylinder-steps");
  write_ring(dir, c);
  const double kappa = 1 + three_g(c.E, c.nu) / H, bound = 4 * kappa * c.tol;
  c.times = "[0.625, 0.71875, 0.8125, 0.90625, 1]";
  auto yaml = [&](const Scheme& s) { return c.yaml(s); };
  std::vector<std::unique_ptr<SchemeRun>> runs;
  for (const Scheme& s : schemes_for(0.1))
    runs.push_back(run_scheme(dir.path(), s, yaml, "steps4"));
  const SchemeRun* newton = runs.front().get();
  ASSERT_TRUE(newton->converged()) << newton->run->result.failure;
  for (const auto& r : runs) {
    SCOPED_TRACE(r->s.label());
    EXPECT_EQ(r->converged(), r->s.converges) << r->run->result.failure;
    if (!r->converged()) {
      report(
          fmt::format("cylinder 4 steps: {:<26} NOT CONVERGED ({} iterations, {} "
                      "factorizations)",
                      r->s.label(), r->run->result.iterations, r->run->result.factorizations));
      continue;
    }
    const SchemeDifference d = difference(r->model(), r->state(), newton->state(), bound);
    report(
        fmt::format("cylinder 4 steps: {:<26} iterations {:4d} factorizations {:3d} {:5.2f} s "
                    "| vs newton: u field {:.1e} eps_p max {:.1e}",
                    r->s.label(), r->run->result.iterations, r->run->result.factorizations,
                    r->seconds, d.u_field, d.ep_max));
    check_within(d, bound);
  }
}

// ------------------------------------------------------------------------------------------
// Plate with a central hole in tension: a quarter (x, y ≥ 0; symmetry on x = 0 and y = 0) of a
// plate 2W wide and 2L long with a hole of radius R, half of the thickness modelled (z = 0 the
// mid-plane, held in z). Three structured blocks of quadrilaterals (two around the hole, split
// at 45°, graded towards it, and the rectangle above), extruded in one layer of hexahedra;
// order 2 in the case. Regions: body; xsym ysym mid; top (y = L, loaded); hole.
std::string quarter_plate_hole_geo(double W, double L, double R, double t, int na, int nr, int ny,
                                   double grading) {
  return fmt::format(R"(W = {}; L = {}; R = {}; t = {};
c = R / Sqrt(2);
Point(1) = {{0, 0, 0}};
Point(2) = {{R, 0, 0}}; Point(3) = {{W, 0, 0}}; Point(4) = {{W, W, 0}}; Point(5) = {{c, c, 0}};
Point(6) = {{0, R, 0}}; Point(7) = {{0, W, 0}}; Point(8) = {{W, L, 0}}; Point(9) = {{0, L, 0}};
Line(1) = {{2, 3}}; Line(2) = {{3, 4}}; Line(3) = {{5, 4}}; Circle(4) = {{2, 1, 5}};
Circle(5) = {{5, 1, 6}}; Line(6) = {{6, 7}}; Line(7) = {{7, 4}};
Line(8) = {{4, 8}}; Line(9) = {{8, 9}}; Line(10) = {{9, 7}};
Curve Loop(1) = {{1, 2, -3, -4}}; Plane Surface(1) = {{1}};
Curve Loop(2) = {{3, -7, -6, -5}}; Plane Surface(2) = {{2}};
Curve Loop(3) = {{7, 8, 9, 10}}; Plane Surface(3) = {{3}};
Transfinite Curve{{1, 3, 6}} = {} Using Progression {};
Transfinite Curve{{2, 4, 5, 7, 9}} = {};
Transfinite Curve{{8, 10}} = {};
Transfinite Surface{{1, 2, 3}};
Recombine Surface{{1, 2, 3}};
e1[] = Extrude {{0, 0, t}} {{ Surface{{1}}; Layers{{1}}; Recombine; }};
e2[] = Extrude {{0, 0, t}} {{ Surface{{2}}; Layers{{1}}; Recombine; }};
e3[] = Extrude {{0, 0, t}} {{ Surface{{3}}; Layers{{1}}; Recombine; }};
Physical Volume("body") = {{e1[1], e2[1], e3[1]}};
Physical Surface("mid") = {{1, 2, 3}};
Physical Surface("ysym") = {{e1[2]}};
Physical Surface("xsym") = {{e2[4], e3[5]}};
Physical Surface("top") = {{e3[4]}};
Physical Surface("hole") = {{e1[5], e2[5]}};
)",
                     num(W), num(L), num(R), num(t), nr + 1, num(grading), na + 1, ny + 1);
}

// W = 1, L = 2, R = 0.25 (hole diameter a quarter of the width), half-thickness 0.1; E = 200
// GPa, ν = 0.3, σ_y = 240 MPa, H = E/10. The gross stress S that makes the net section yield
// (the limit of a perfectly plastic plate) is σ_y(1 − R/W) = 180 MPa; the stress concentration
// (Heywood: K_t,net = 2 + (1 − 2R/2W)³ = 2.42, K_t,gross = 3.23) yields the hole edge at
// S ≈ 74 MPa. One elastic step to S = 58 MPa, then one step to S = 144 MPa (0.8 of the
// net-section limit): a plastic zone around the hole, ε̃^p ≈ 2e-3 at its edge.
TEST(VerifyPlasticSchemes, PlateWithHoleLinearHardeningOnePlasticStep) {
  const double W = 1, L = 2, R = 0.25, E = 2e11, nu = 0.3, sy = 2.4e8, H = E / 10, tol = 1e-8;
  const double S = 0.8 * sy * (1 - R / W);
  TempDir dir("schemes-plate");
  write_file(dir / "plate.geo", quarter_plate_hole_geo(W, L, R, 0.1, 8, 8, 6, 1.25));
  auto yaml = [&](const Scheme& s) {
    return fmt::format(
        "mesh: {{file: plate.geo, order: 2}}\n"
        "materials:\n  - {{E: {}, nu: {}, plasticity: {{linear: {{yield: {}, hardening: {}}}}}}}\n"
        "boundary:\n"
        "  - {{region: xsym, displacement: {{x: 0}}}}\n"
        "  - {{region: ysym, displacement: {{y: 0}}}}\n"
        "  - {{region: mid, displacement: {{z: 0}}}}\n"
        "  - {{region: top, traction: [0, \"{}*t\", 0]}}\n"
        "solver: {{scheme: {}, curve_form: {}, relaxation: {}, times: [0.4, 1], tolerance: {}, "
        "max_iterations: {}, cutback: 0}}\n"
        "output:\n  probes:\n"
        "    - {{name: hole_side, point: [{}, 0, 0]}}\n"
        "    - {{name: hole_top, point: [0, {}, 0]}}\n"
        "    - {{name: ligament_end, point: [{}, 0, 0]}}\n"
        "    - {{name: end, point: [0, {}, 0]}}\n",
        num(E), num(nu), num(sy), num(H), num(S), s.scheme, s.form, num(s.omega), num(tol),
        s.max_iterations, num(R), num(R), num(W), num(L));
  };
  const double kappa = 1 + three_g(E, nu) / H;
  auto runs = every_scheme(dir.path(), "plate with hole", schemes_for(0.1), yaml, tol,
                           [&](const SchemeRun&) { return kappa; });
  ASSERT_TRUE(runs.front()->converged());
  // A plastic zone around the hole, contained: a small part of the volume, and the outer end
  // of the ligament (x = W, y = 0) elastic.
  const SchemeRun& n = *runs.front();
  const SchemeDifference d = difference(n.model(), n.state(), n.state(), 0.0);
  const RecoveredFields f = recover_fields(n.model(), n.state());
  const ProbeValues edge = probe_values(n.model(), n.model().probes()[0], n.state(),
                                        f.nodal_stress, f.nodal_eps_p_eq);
  const ProbeValues end = probe_values(n.model(), n.model().probes()[2], n.state(),
                                       f.nodal_stress, f.nodal_eps_p_eq);
  report(
      fmt::format("plate with hole: newton: {} plastic points of {} ({:.1f} % of the volume); "
                  "at the hole edge sigma_yy {:.4g} eps_p {:.3e}; at the ligament end eps_p {:.1e}",
                  d.zone_ref, n.model().n_points(), 100 * d.zone_fraction, edge.stress[1],
                  edge.equivalent_plastic_strain, end.equivalent_plastic_strain));
  EXPECT_GT(edge.equivalent_plastic_strain, 1e-3);
  EXPECT_LT(d.zone_fraction, 0.2);
  EXPECT_EQ(end.equivalent_plastic_strain, 0.0);
}

}  // namespace
}  // namespace hencky::verify
