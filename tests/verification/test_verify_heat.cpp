// Verification of heat conduction (the heat section) against closed forms: a slab with a
// conductivity linear in T (Kirchhoff transform), radiation into surroundings, a semi-infinite
// body with a sudden surface temperature (erfc, and the observed order in time of backward
// Euler and Crank–Nicolson), a slab cooled by convection (the eigenfunction series), and the
// heat balance of a transient with every kind of condition and a c(T) table.
#include <gtest/gtest.h>

#include "verify_support.hpp"

using namespace hencky;
using namespace hencky::verify;

namespace {

/// The bar [0, L] x [0, w] x [0, w]: n hexahedra along x (20-node when quadratic), one across.
/// Regions: body; x0, x1 (the ends), sides (the four long faces).
std::string bar_msh(int n, double L, double w, bool quadratic) {
  MshBuilder b;
  auto id = [&](int i, int j, int k) { return 1 + i + (n + 1) * (j + 2 * k); };
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i <= n; ++i) b.x.emplace_back(L * i / n, w * j, w * k);
  for (int i = 0; i < n; ++i) {
    const std::array<int, 8> c{id(i, 0, 0), id(i + 1, 0, 0), id(i + 1, 1, 0), id(i, 1, 0),
                               id(i, 0, 1), id(i + 1, 0, 1), id(i + 1, 1, 1), id(i, 1, 1)};
    b.hex(c, quadratic, 1);
    if (i == 0) b.quad(c[0], c[3], c[7], c[4], quadratic, 11);
    if (i == n - 1) b.quad(c[1], c[2], c[6], c[5], quadratic, 12);
    b.quad(c[0], c[1], c[5], c[4], quadratic, 13);
    b.quad(c[3], c[2], c[6], c[7], quadratic, 13);
    b.quad(c[0], c[1], c[2], c[3], quadratic, 13);
    b.quad(c[4], c[5], c[6], c[7], quadratic, 13);
  }
  return b.text({{3, 1, "body"}, {2, 11, "x0"}, {2, 12, "x1"}, {2, 13, "sides"}});
}

/// A bar case: elastic steel-like constants (the mechanics only has to run: the end x0 is
/// clamped), the given heat properties, heat section and solver lines.
std::string bar_case(const std::string& properties, const std::string& heat,
                     const std::string& solver) {
  return "mesh: {file: bar.msh}\n"
         "materials:\n"
         "  - {name: m, E: 2.0e11, nu: 0.3, alpha: 1.0e-5, " +
         properties +
         "}\n"
         "temperature: {reference: 0, from: heat}\n"
         "heat:\n" +
         heat +
         "boundary:\n"
         "  - {region: x0, displacement: {x: 0, y: 0, z: 0}}\n"
         "solver: " +
         solver + "\n";
}

/// Max |T_h − T| over the nodes of the bar's axis y = z = 0.
double axis_error(const Model& model, const std::vector<double>& T,
                  const std::function<double(double)>& exact, double* scale = nullptr) {
  double e = 0, s = 0;
  for (int n = 0; n < model.mesh().n_nodes(); ++n) {
    const Vec3& x = model.mesh().x[n];
    if (std::abs(x.y()) > 1e-12 || std::abs(x.z()) > 1e-12) continue;
    e = std::max(e, std::abs(T[n] - exact(x.x())));
    s = std::max(s, std::abs(exact(x.x())));
  }
  if (scale) *scale = s;
  return e;
}

/// The flow of heat.boundary entry b of the state, W into the body.
double flow(const State& s, std::size_t b) {
  return s.heat_flow.at(b);
}

}  // namespace

// ------------------------------------------------------------------------------------------
// Steady slab, k(T) = k0 (1 + β T) between T(0) = T0 and T(L) = 0, no source. With the
// Kirchhoff variable U(T) = ∫_0^T k = k0 (T + β T²/2), U is linear in x:
//   T(x) = (−1 + sqrt(1 + 2 β U0 (1 − x/L) / k0)) / β,  heat into x0 = U0 A / L = −heat into x1.
TEST(VerifyHeat, SlabWithLinearConductivityMeetsTheKirchhoffSolution) {
  const double L = 1, w = 0.1, k0 = 10, beta = 2e-3, T0 = 500;
  const double U0 = k0 * (T0 + beta * T0 * T0 / 2), A = w * w;
  auto exact = [&](double x) {
    return (-1 + std::sqrt(1 + 2 * beta * U0 * (1 - x / L) / k0)) / beta;
  };
  for (bool quadratic : {false, true}) {
    std::vector<double> h, e, eq;
    for (int n : {4, 8, 16}) {
      TempDir dir(fmt::format("heat-slab-{}-{}", quadratic, n));
      write_file(dir / "bar.msh", bar_msh(n, L, w, quadratic));
      auto r = run_case(dir.path(),
                        bar_case(fmt::format("conductivity: {{temperature: [0, 1000], value: "
                                             "[{}, {}]}}",
                                             num(k0), num(k0 * (1 + 1000 * beta))),
                                 "  tolerance: 1.0e-12\n  boundary:\n"
                                 "    - {region: x0, temperature: 500}\n"
                                 "    - {region: x1, temperature: 0}\n",
                                 "{steps: 1}"));
      double s = 0;
      const double err = axis_error(r->model(), r->state().nodal_temperature, exact, &s) / s;
      const double q0 = flow(r->state(), 0), q1 = flow(r->state(), 1);
      const double qerr = std::abs(q0 - U0 * A / L) / (U0 * A / L);
      const int its = r->run->heat_iterations, gm = r->run->heat_gmres_iterations;
      report(
          fmt::format("heat slab k(T) {} n {:2d}: max nodal error {:.3e}, flow in {:.6g} out "
                      "{:.6g} (exact {:.6g}), flow error {:.3e}; {} Newton iterations "
                      "({} GMRES) for both solves (t = 0 and 1)",
                      quadratic ? "hex20" : "hex8", n, err, q0, q1, U0 * A / L, qerr, its, gm));
      EXPECT_LE(its, 12) << "Newton converges quadratically";
      EXPECT_NEAR(q0 + q1, 0.0, 1e-9 * std::abs(q0)) << "the heat in leaves";
      h.push_back(L / n);
      e.push_back(err);
      eq.push_back(qerr);
    }
    // Linear elements: with k linear in T and T linear on a cell, ∫ k(T) T' dx over the cell is
    // U(T_right) − U(T_left) exactly (two-point Gauss), so the nodal equations are those of
    // U: the nodal values are exact. Quadratic ones: exact flows, nodal errors of third order.
    // In 1D without source the flow is constant, and the ends' reactions give it exactly.
    for (std::size_t i = 0; i < e.size(); ++i) {
      EXPECT_LT(eq[i], 1e-12);
      if (!quadratic) {
        EXPECT_LT(e[i], 1e-12);
      }
    }
    if (quadratic) {
      const double rate = observed_rate(h, e);
      report(fmt::format("heat slab k(T) hex20: observed nodal rate {:.2f}", rate));
      EXPECT_GT(rate, 3.2);
    }
  }
}

// ------------------------------------------------------------------------------------------
// Radiation: a bar held at T0 at x0 radiating from x1 into surroundings at T_inf (constant k,
// no source). T is linear in x, which the elements hold exactly, and the end temperature T1
// solves k (T0 − T1) / L = ε σ ((T1 − Z)⁴ − (T_inf − Z)⁴) (Z the absolute zero): Newton meets
// it to the tolerance, in the few iterations of a quadratic convergence.
TEST(VerifyHeat, RadiatingBarEndMeetsTheBalanceOfConductionAndRadiation) {
  const double L = 0.5, w = 0.05, k = 15, T0 = 800, Tinf = 20, eps = 0.7, Z = -273.15,
               sigma = 5.670374419e-8;
  auto balance = [&](double T1) {
    return k * (T0 - T1) / L - eps * sigma * (std::pow(T1 - Z, 4) - std::pow(Tinf - Z, 4));
  };
  double lo = Tinf, hi = T0;  // balance(lo) > 0 > balance(hi)
  for (int i = 0; i < 200; ++i) (balance(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  const double T1 = 0.5 * (lo + hi);
  TempDir dir("heat-radiation");
  write_file(dir / "bar.msh", bar_msh(6, L, w, false));
  auto r =
      run_case(dir.path(), bar_case(fmt::format("conductivity: {}", num(k)),
                                    fmt::format("  absolute_zero: {}\n  tolerance: 1.0e-12\n"
                                                "  boundary:\n"
                                                "    - {{region: x0, temperature: {}}}\n"
                                                "    - {{region: x1, radiation: {{emissivity: {}, "
                                                "ambient: {}}}}}\n",
                                                num(Z), num(T0), num(eps), num(Tinf)),
                                    "{steps: 1}"));
  const double err = axis_error(r->model(), r->state().nodal_temperature,
                                [&](double x) { return T0 + (T1 - T0) * x / L; });
  const double q = k * (T0 - T1) / L * w * w;
  report(
      fmt::format("heat radiation: T(L) exact {:.10g}, max nodal error {:.3e}; flows {:.8g} "
                  "{:.8g} (exact ±{:.8g})",
                  T1, err, flow(r->state(), 0), flow(r->state(), 1), q));
  EXPECT_LT(err, 1e-8 * T0);
  EXPECT_NEAR(flow(r->state(), 0), q, 1e-8 * q);
  EXPECT_NEAR(flow(r->state(), 1), -q, 1e-8 * q);
}

// ------------------------------------------------------------------------------------------
// A semi-infinite body x >= 0 at T = 0 whose surface is held at T_s from t = 0:
//   T = T_s erfc(x / (2 sqrt(κ t))), κ = k / (ρ c).
// The bar is 5 diffusion lengths 2 sqrt(κ t_end) long (erfc(5) < 2e-12). The order in time is
// measured against the same mesh with 32 times smaller steps, which removes the error in
// space; the error against erfc of the finest run is reported besides.
namespace {

struct Transient {
  std::vector<double> T;  ///< nodal temperatures at t_end
  std::unique_ptr<SteppedRun> run;
};

Transient erfc_run(int steps, double theta, const std::string& mesh_dir_tag) {
  TempDir dir(fmt::format("heat-erfc-{}-{}-{}", mesh_dir_tag, steps, theta));
  write_file(dir / "bar.msh", bar_msh(40, 1.0, 0.05, true));
  auto run = run_stepped(dir.path(),
                         bar_case("conductivity: 1, density: 1, specific_heat: 1",
                                  fmt::format("  analysis: transient\n  theta: {}\n  initial: 0\n"
                                              "  tolerance: 1.0e-12\n"
                                              "  boundary:\n    - {{region: x0, temperature: 1}}\n",
                                              num(theta)),
                                  fmt::format("{{steps: {}, end: 0.01}}", steps)));
  EXPECT_EQ(run->result.status, AnalysisStatus::converged) << run->result.failure;
  Transient out;
  out.T = run->all.states.back().nodal_temperature;
  out.run = std::move(run);
  return out;
}

}  // namespace

TEST(VerifyHeat, SuddenSurfaceTemperatureConvergesInTimeAtTheOrderOfTheMethod) {
  const double t_end = 0.01;
  auto erfc_exact = [&](double x) { return std::erfc(x / (2 * std::sqrt(t_end))); };
  for (double theta : {1.0, 0.5}) {
    const Transient ref = erfc_run(640, theta, "ref");
    const Model& model = ref.run->model();
    std::vector<double> h, e;
    for (int steps : {20, 40, 80}) {
      const Transient t = erfc_run(steps, theta, "run");
      double err = 0;
      for (std::size_t n = 0; n < t.T.size(); ++n) err = std::max(err, std::abs(t.T[n] - ref.T[n]));
      report(fmt::format("heat erfc theta {}: {:3d} steps, max |T - T_ref(dt/32)| {:.3e}", theta,
                         steps, err));
      h.push_back(t_end / steps);
      e.push_back(err);
    }
    const double rate = observed_rate(h, e);
    const double exact_err = axis_error(model, ref.T, erfc_exact);
    report(
        fmt::format("heat erfc theta {}: observed order in time {:.2f}; 640 steps vs erfc: max "
                    "nodal error {:.3e}",
                    theta, rate, exact_err));
    EXPECT_GT(rate, theta == 1.0 ? 0.9 : 1.9);
    EXPECT_LT(rate, theta == 1.0 ? 1.2 : 2.3);
    EXPECT_LT(exact_err, 2e-3);
  }
}

// ------------------------------------------------------------------------------------------
// A slab −L <= x <= L at T_i cooled on both faces by convection h into T_inf = 0 (the bar is its
// half 0 <= x <= L, insulated at x = 0 by symmetry): with Bi = h L / k,
//   T/T_i = Σ C_n exp(−ζ_n² Fo) cos(ζ_n x/L),  ζ_n tan ζ_n = Bi,  C_n = 4 sin ζ_n / (2ζ_n + sin
//   2ζ_n),
// Fo = κ t / L² (Incropera, §5.5).
TEST(VerifyHeat, ConvectivelyCooledSlabMeetsTheSeriesSolution) {
  const double L = 0.1, k = 20, rho = 8000, c = 500, h = 400, Ti = 500;
  const double kappa = k / (rho * c), Bi = h * L / k, t_end = 0.5 * L * L / kappa;  // Fo = 0.5
  std::vector<double> zeta;
  for (int n = 0; n < 60; ++n) {  // ζ_n in (nπ, nπ + π/2)
    double lo = n * M_PI + 1e-12, hi = n * M_PI + M_PI / 2 - 1e-12;
    for (int i = 0; i < 200; ++i) {
      const double m = 0.5 * (lo + hi);
      (m * std::tan(m) < Bi ? lo : hi) = m;
    }
    zeta.push_back(0.5 * (lo + hi));
  }
  auto exact = [&](double x, double t) {
    double s = 0;
    for (double z : zeta)
      s += 4 * std::sin(z) / (2 * z + std::sin(2 * z)) * std::exp(-z * z * kappa * t / (L * L)) *
           std::cos(z * x / L);
    return Ti * s;
  };
  TempDir dir("heat-cooled-slab");
  write_file(dir / "bar.msh", bar_msh(16, L, 0.01, true));
  auto run = run_stepped(
      dir.path(),
      bar_case(
          fmt::format("conductivity: {}, density: {}, specific_heat: {}", num(k), num(rho), num(c)),
          fmt::format("  analysis: transient\n  theta: 0.5\n  initial: {}\n"
                      "  boundary:\n    - {{region: x1, convection: {{h: {}, ambient: 0}}}}\n",
                      num(Ti), num(h)),
          fmt::format("{{steps: 100, end: {}}}", num(t_end))));
  ASSERT_EQ(run->result.status, AnalysisStatus::converged) << run->result.failure;
  double worst = 0;
  for (std::size_t s = 19; s < run->all.states.size(); s += 20) {
    const State& st = run->all.states[s];
    const double e =
        axis_error(run->model(), st.nodal_temperature, [&](double x) { return exact(x, st.time); });
    // The heat leaving by convection: h ∫ (T(L) − 0) dA, against the series (the flow is the
    // mean over the step, which the trapezoidal rule gives to O(Δt²)).
    const double dt = t_end / 100, A = 0.01 * 0.01;
    const double q_exact = -h * A * (0.5 * exact(L, st.time) + 0.5 * exact(L, st.time - dt));
    report(
        fmt::format("heat cooled slab Bi {:.1f}: Fo {:.2f} max nodal error {:.3e} K ({:.2e} of "
                    "T_i); flow {:.6g} W (series {:.6g})",
                    Bi, kappa * st.time / (L * L), e, e / Ti, flow(st, 0), q_exact));
    EXPECT_NEAR(flow(st, 0), q_exact, 5e-4 * std::abs(q_exact));
    worst = std::max(worst, e / Ti);
  }
  EXPECT_LT(worst, 1e-4);
}

// ------------------------------------------------------------------------------------------
// The heat balance of a transient: what the flows of every condition and the source bring in
// over the steps equals the heat stored, ∫ (H(T) − H(T_0)) dV, to the solver's tolerance, for
// backward Euler and Crank–Nicolson, with c(T) a table (H quadratic in T), a source, a flux, a
// convection, a radiation and a fixed temperature, on distorted 20-node hexahedra.
TEST(VerifyHeat, TransientHeatBalanceHoldsToTheSolverTolerance) {
  // c(T) = c0 + c1 T on −1000 .. 1000: the table covers the undershoot of the consistent
  // capacity (steps far shorter than ρc h²/k, near the sudden heating of x0) below 0 °C.
  const double rho = 7800, c0 = 450, c1 = 0.2, Q = 2e6;
  // Backward Euler and Crank–Nicolson on the mechanical steps, and Crank–Nicolson on three heat
  // steps per mechanical one (the flows are then the means over the mechanical steps).
  for (auto [theta, heat_steps] : {std::pair{1.0, 0}, std::pair{0.5, 0}, std::pair{0.5, 24}}) {
    TempDir dir(fmt::format("heat-balance-{}-{}", theta, heat_steps));
    write_file(dir / "cube.msh", cube_msh(3, GridCells::hex20, 0.2, 0.1));
    auto run = run_stepped(
        dir.path(),
        fmt::format(
            "mesh: {{file: cube.msh}}\n"
            "materials:\n"
            "  - {{name: m, E: 2.0e11, nu: 0.3, alpha: 1.0e-5, conductivity: 30, density: {},\n"
            "     specific_heat: {{temperature: [-1000, 1000], value: [{}, {}]}}}}\n"
            "temperature: {{reference: 20, from: heat}}\n"
            "heat:\n  analysis: transient\n  theta: {}\n  initial: 20\n  source: {}\n{}"
            "  absolute_zero: -273.15\n  tolerance: 1.0e-12\n"
            "  boundary:\n"
            "    - {{region: x0, temperature: \"20 + 300*t\"}}\n"
            "    - {{region: z1, flux: \"5.0e4*(1 - t)\"}}\n"
            "    - {{region: x1, convection: {{h: 50, ambient: 20}}}}\n"
            "    - {{region: y1, radiation: {{emissivity: 0.9, ambient: 20}}}}\n"
            "boundary:\n  - {{region: z0, displacement: {{x: 0, y: 0, z: 0}}}}\n"
            "solver: {{steps: 8, end: 1.0}}\n",
            num(rho), num(c0 - 1000 * c1), num(c0 + 1000 * c1), num(theta), num(Q),
            heat_steps ? fmt::format("  steps: {}\n", heat_steps) : std::string()));
    ASSERT_EQ(run->result.status, AnalysisStatus::converged) << run->result.failure;
    // Heat brought in: Σ over the steps of Δt (Σ flows + Q V).
    const double V = 0.1 * 0.1 * 0.1;
    double in = 0, t0 = 0;
    for (const State& s : run->all.states) {
      double q = Q * V;
      for (double f : s.heat_flow) q += f;
      in += (s.time - t0) * q;
      t0 = s.time;
    }
    // Heat stored: ∫ ρ (H(T) − H(20)) dV with H(T) = c0 T + c1 T²/2, by the solver's own rule
    // for 20-node hexahedra (degree 5): the discrete balance holds for the discrete integrals.
    const Model& model = run->model();
    const auto& T = run->all.states.back().nodal_temperature;
    auto H = [&](double v) { return rho * (c0 * v + c1 * v * v / 2); };
    double stored = 0;
    Vec3 x[max_cell_nodes];
    double dNdx[3 * max_cell_nodes];
    for (int e = 0; e < model.mesh().cells.size(); ++e) {
      const auto nodes = model.mesh().cells.nodes(e);
      const int n = static_cast<int>(nodes.size());
      const auto& tab = reference_table(model.mesh().cells.type[e], 5);
      for (int a = 0; a < n; ++a) x[a] = model.mesh().x[nodes[a]];
      for (int q = 0; q < tab.n_points; ++q) {
        const double dv =
            physical_gradients(tab, q, std::span<const Vec3>(x, n), dNdx) * tab.weights[q];
        double Tq = 0;
        for (int a = 0; a < n; ++a) Tq += tab.N[q * n + a] * T[nodes[a]];
        stored += (H(Tq) - H(20)) * dv;
      }
    }
    report(fmt::format(
        "heat balance theta {} heat steps {}: brought in {:.10g} J, stored {:.10g} "
        "J, relative difference {:.2e}",
        theta, heat_steps ? heat_steps : 8, in, stored, std::abs(in - stored) / std::abs(stored)));
    EXPECT_NEAR(in, stored, 1e-8 * std::abs(stored));
  }
}
