#include "solve/analysis.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <deque>

#include "fem/geometry.hpp"
#include "fem/reference_element.hpp"

namespace hencky {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double norm(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s);
}

class StepSolver {
 public:
  StepSolver(const Model& m, LinearSolver& solver, Log& log, Timings& timings)
      : m_(m), solver_(solver), log_(log), timings_(timings) {
    values_.resize(m.assembler().pattern().nnz());
    matrix_changes_with_temperature_ = false;
    if (m.has_temperature())
      for (const auto& mat : m.materials())
        matrix_changes_with_temperature_ = matrix_changes_with_temperature_ ||
                                           !mat.spec->E.is_constant() ||
                                           !mat.spec->nu.is_constant();
  }

  /// The initial state: undeformed, stress-free, at T_ref, no load.
  State initial_state() const {
    State s;
    const int n_dofs = m_.dofs().n_dofs(), n_pts = m_.n_points();
    s.u.assign(n_dofs, 0.0);
    s.nodal_temperature.assign(m_.mesh().n_nodes(), m_.reference_temperature());
    s.stress.assign(n_pts, Voigt::Zero());
    s.temperature.assign(n_pts, m_.reference_temperature());
    s.constants.resize(n_pts);
    for (int e = 0; e < m_.mesh().cells.size(); ++e)
      for (int p = m_.point_offset(e); p < m_.point_offset(e + 1); ++p)
        s.constants[p] = m_.material_of(e).at(m_.reference_temperature());
    s.f_ext.assign(n_dofs, 0.0);
    s.f_int.assign(n_dofs, 0.0);
    return s;
  }

  /// One step from `c` (committed at c.time) to time t1. Returns true when it converged and
  /// fills `trial`; `iterations` and `residual` describe the last iterate either way.
  bool step(const State& c, double t1, State& trial, int& iterations, double& residual) {
    const auto& dofs = m_.dofs();
    const auto& spec = m_.spec().solver;
    trial.time = t1;
    trial.u = c.u;
    m_.nodal_temperature(t1, trial.nodal_temperature);
    point_temperatures(trial);
    m_.prescribed_displacement(t1, trial.u);  // prescribed entries of u at t1, free ones at t
    m_.external_forces(t1, trial.f_ext);

    // Equilibrium target of the step, (2.29)-(2.30): F(t+Δt) − (1 − γ)·R(t), R(t) = F(t) − F_int(t):
    // with γ = 1 the defect left by the previous step is corrected in full.
    const double gamma = spec.correction;
    target_.resize(dofs.n_dofs());
    for (int i = 0; i < dofs.n_dofs(); ++i)
      target_[i] = trial.f_ext[i] - (1 - gamma) * (c.f_ext[i] - c.f_int[i]);

    const bool new_matrix = !factorized_ || matrix_changes_with_temperature_;
    std::vector<double>& rhs = rhs_;
    rhs.resize(dofs.n_free);
    delta_.resize(dofs.n_free);
    // Force scale of the step, fixed at the predictor: the loads, the internal forces before and
    // after the predictor, and the predictor's residual (which carries thermal and prescribed-
    // displacement loading). A step whose answer has no load and no stress (free expansion,
    // unloading to zero) still has a scale, so round-off is recognised as convergence.
    double f_norm = 0;
    for (iterations = 0;; ++iterations) {
      update_points(c, trial);
      for (int i = 0; i < dofs.n_dofs(); ++i)
        if (int k = dofs.eq[i]; k >= 0) rhs[k] = target_[i] - trial.f_int[i];
      double r = 0;
      for (double v : rhs) r += v * v;
      if (iterations == 0)
        f_norm = std::max({norm(trial.f_ext), norm(c.f_int), norm(trial.f_int), std::sqrt(r)});
      residual = f_norm > 0 ? std::sqrt(r) / f_norm : 0.0;
      log_.detail("  iteration {}: relative residual {:.3e}", iterations, residual);
      if (iterations >= 1 && residual <= spec.tolerance) {
        // The reported residual is the true equilibrium defect F − F_int (γ only shifts the target).
        residual = f_norm > 0 ? equilibrium_defect(trial) / f_norm : 0.0;
        return true;
      }
      if (iterations >= spec.max_iterations || !std::isfinite(residual)) return false;
      if (iterations == 0 && new_matrix) assemble_and_factorize(trial);
      auto t0 = Clock::now();
      solver_.solve(rhs, delta_);
      timings_.solve += seconds_since(t0);
      for (int i = 0; i < dofs.n_dofs(); ++i)
        if (int k = dofs.eq[i]; k >= 0) trial.u[i] += delta_[k];
    }
  }

  double equilibrium_defect(const State& s) const {
    double r = 0;
    for (int i = 0; i < m_.dofs().n_dofs(); ++i)
      if (m_.dofs().eq[i] >= 0) r += (s.f_ext[i] - s.f_int[i]) * (s.f_ext[i] - s.f_int[i]);
    return std::sqrt(r);
  }

 private:
  void point_temperatures(State& s) {
    const auto& mesh = m_.mesh();
    s.temperature.resize(m_.n_points());
    s.constants.resize(m_.n_points());
    const int n_mat = static_cast<int>(m_.materials().size());
    std::vector<double> t_min(n_mat, INFINITY), t_max(n_mat, -INFINITY);
    for (int e = 0; e < mesh.cells.size(); ++e) {
      const auto nodes = mesh.cells.nodes(e);
      const auto& tab = reference_table(mesh.cells.type[e]);
      const auto& mat = m_.material_of(e);
      const int mi = m_.material_index(e);
      for (int q = 0; q < tab.n_points; ++q) {
        const double* N = &tab.N[static_cast<std::size_t>(q) * tab.n_nodes];
        double T = 0;
        for (std::size_t a = 0; a < nodes.size(); ++a) T += N[a] * s.nodal_temperature[nodes[a]];
        const int p = m_.point_offset(e) + q;
        s.temperature[p] = T;
        s.constants[p] = mat.at(T);
        t_min[mi] = std::min(t_min[mi], T);
        t_max[mi] = std::max(t_max[mi], T);
      }
    }
    for (int k = 0; k < n_mat; ++k)
      if (t_min[k] <= t_max[k]) m_.materials()[k].warn_outside(t_min[k], t_max[k], log_);
  }

  /// Point update and internal forces: σ = σ(t) + D(t+Δt)(Δε − Δε^th), (1.9), (1.12).
  void update_points(const State& c, State& trial) {
    auto t0 = Clock::now();
    const auto& mesh = m_.mesh();
    trial.f_int.assign(m_.dofs().n_dofs(), 0.0);
    m_.assembler().vector(
        [&](int e, CellBuffers& b) {
          const auto nodes = mesh.cells.nodes(e);
          const int n = static_cast<int>(nodes.size());
          const auto& tab = reference_table(mesh.cells.type[e]);
          Vec3 x[max_cell_nodes];
          double du[3 * max_cell_nodes], dNdx[3 * max_cell_nodes];
          for (int a = 0; a < n; ++a) {
            x[a] = mesh.x[nodes[a]];
            for (int d = 0; d < 3; ++d) du[3 * a + d] = trial.u[3 * nodes[a] + d] - c.u[3 * nodes[a] + d];
          }
          for (int q = 0; q < tab.n_points; ++q) {
            const double det = physical_gradients(tab, q, std::span<const Vec3>(x, n), dNdx);
            const int p = m_.point_offset(e) + q;
            const Voigt d_eps = strain_from_gradients(n, dNdx, du);
            trial.stress[p] = elastic_stress_update(c.constants[p], c.temperature[p],
                                                    trial.constants[p], trial.temperature[p],
                                                    c.stress[p], d_eps);
            add_bt_sigma(n, dNdx, trial.stress[p], det * tab.weights[q], b.fe);
          }
        },
        trial.f_int);
    timings_.material += seconds_since(t0);
  }

  void assemble_and_factorize(const State& trial) {
    auto t0 = Clock::now();
    const auto& mesh = m_.mesh();
    scratch_.assign(m_.dofs().n_dofs(), 0.0);
    m_.assembler().matrix_and_vector(
        [&](int e, CellBuffers& b) {
          const auto nodes = mesh.cells.nodes(e);
          const int n = static_cast<int>(nodes.size());
          const int nd = 3 * n;
          const auto& tab = reference_table(mesh.cells.type[e]);
          Vec3 x[max_cell_nodes];
          double dNdx[3 * max_cell_nodes];
          for (int a = 0; a < n; ++a) x[a] = mesh.x[nodes[a]];
          for (int q = 0; q < tab.n_points; ++q) {
            const double w = physical_gradients(tab, q, std::span<const Vec3>(x, n), dNdx) *
                             tab.weights[q];
            const int p = m_.point_offset(e) + q;
            const ElasticConstants& k = trial.constants[p];
            const double lam = k.lame_lambda() * w, mu = k.shear_modulus() * w;
            // K_ab = B_aᵀ D B_b for isotropic D: λ g_a g_bᵀ + μ (g_b g_aᵀ + (g_a·g_b) I).
            for (int a = 0; a < n; ++a) {
              const Vec3 ga(dNdx[3 * a], dNdx[3 * a + 1], dNdx[3 * a + 2]);
              for (int bb = a; bb < n; ++bb) {
                const Vec3 gb(dNdx[3 * bb], dNdx[3 * bb + 1], dNdx[3 * bb + 2]);
                const double dot = mu * ga.dot(gb);
                for (int i = 0; i < 3; ++i)
                  for (int j = 0; j < 3; ++j) {
                    const double v = lam * ga[i] * gb[j] + mu * gb[i] * ga[j] + (i == j ? dot : 0.0);
                    b.ke[(3 * a + i) * nd + 3 * bb + j] += v;
                  }
              }
            }
          }
          // Lower blocks by symmetry.
          for (int a = 0; a < n; ++a)
            for (int bb = a + 1; bb < n; ++bb)
              for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                  b.ke[(3 * bb + j) * nd + 3 * a + i] = b.ke[(3 * a + i) * nd + 3 * bb + j];
        },
        values_, scratch_);
    timings_.assembly += seconds_since(t0);
    t0 = Clock::now();
    if (!analyzed_) {
      solver_.analyze(m_.assembler().pattern());
      analyzed_ = true;
    }
    solver_.factorize(values_);
    factorized_ = true;
    timings_.factorization += seconds_since(t0);
  }

  const Model& m_;
  LinearSolver& solver_;
  Log& log_;
  Timings& timings_;
  bool matrix_changes_with_temperature_ = false;
  bool analyzed_ = false, factorized_ = false;
  std::vector<double> values_, scratch_, target_, rhs_, delta_;
};

}  // namespace

AnalysisResult run_analysis(const Model& model, LinearSolver& solver, Log& log, Timings& timings,
                            StepObserver& observer) {
  const auto& spec = model.spec().solver;
  StepSolver stepper(model, solver, log, timings);
  State committed = stepper.initial_state(), trial = committed;
  AnalysisResult result;

  // Targets still to reach, each with its cut-back depth: a step that fails is replaced by two
  // half steps one level deeper, down to `cutback` levels; the run then stops (status 2).
  struct Target {
    double time;
    int depth;
  };
  std::deque<Target> targets;
  for (double t : spec.times) targets.push_back({t, 0});
  while (!targets.empty()) {
    const double t1 = targets.front().time;
    const int depth = targets.front().depth;
    int iterations = 0;
    double residual = 0;
    bool ok = false;
    std::string why;
    try {
      ok = stepper.step(committed, t1, trial, iterations, residual);
      if (!ok)
        why = fmt::format("no convergence in {} iterations (relative residual {:.3e})",
                          iterations, residual);
    } catch (const SolveError& e) {
      if (result.steps == 0 && iterations == 0)
        throw InputError(SourceLocation{model.spec().file.string(), 0, 0, "boundary"},
                         std::string(e.what()) +
                             ": the body is not held against rigid-body motion (translations "
                             "and rotations); check the displacement conditions");
      why = e.what();
    }
    result.iterations += iterations;
    if (!ok) {
      const double mid = 0.5 * (committed.time + t1);
      if (depth < spec.cutback && mid > committed.time && mid < t1) {
        log.info("step to t = {:g} failed ({}); cutting back to t = {:g}", t1, why, mid);
        targets.front().depth = depth + 1;
        targets.push_front({mid, depth + 1});
        continue;
      }
      result.status = AnalysisStatus::not_converged;
      result.failure = fmt::format("step to t = {:g} did not converge after {} cut-backs: {}", t1,
                                   depth, why);
      log.info("{}", result.failure);
      return result;
    }
    targets.pop_front();
    std::swap(committed, trial);
    ++result.steps;
    StepReport report{result.steps, t1, iterations, residual, targets.empty()};
    log.info("step {:4d}  t = {:<10.6g} iterations {:3d}  residual {:.2e}", report.step,
             report.time, report.iterations, report.residual);
    const auto t0 = Clock::now();
    observer.step_done(report, committed);
    timings.output += seconds_since(t0);
  }
  return result;
}

}  // namespace hencky
