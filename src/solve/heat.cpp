// The heat analysis's steps (solve/heat.hpp): the start, the Newton iteration of a step, the
// cut-backs, and the snapshots the mechanical steps read. The passes over the cells are in
// heat_assembly.cpp, the terms at a point in heat_terms.cpp.
#include "solve/heat.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "core/interrupt.hpp"
#include "core/invariant.hpp"
#include "core/timer.hpp"
#include "linalg/gmres.hpp"
#include "parallel/mpi.hpp"
#include "parallel/nodal_layout.hpp"
#include "solve/heat_terms.hpp"

namespace hencky {

namespace {

/// The norm of a nodal vector over the free nodes: each node counted once over the ranks (a
/// distributed mesh's ghosts are left to their owners).
double norm(const NodalLayout& layout, const std::vector<double>& v, const std::vector<int>& eq) {
  const std::size_t own = layout.owned_entries(v.size(), 1, static_cast<int>(v.size()));
  double s = 0;
  for (std::size_t n = 0; n < own; ++n)
    if (eq[n] >= 0) s += v[n] * v[n];
  return std::sqrt(layout.total(s));
}

}  // namespace

HeatSolver::HeatSolver(const Model& model, const SystemFactory& make_system, Log& log)
    : model_(model), spec_(model.spec().heat), log_(log) {
  system_ = make_system(model.heat_assembler(), model.heat_dofs());
  const double T_ref = model.reference_temperature();
  for (const MaterialModel& m : model.materials())
    capacity_.push_back(spec_.transient
                            ? HeatCapacity(m.spec->density, m.spec->specific_heat, T_ref)
                            : HeatCapacity());
  HeatExpressions ex{spec_.source, {}, {}};
  for (const auto& b : spec_.boundary) {
    ex.value.push_back(b.value);
    ex.ambient.push_back(b.ambient);
  }
  expressions_.assign(static_cast<std::size_t>(std::max(1, omp_get_max_threads())), ex);

  // The matrix depends on Δt alone when every property is a constant, the film coefficients
  // are constants and nothing radiates or makes a source of the temperature.
  // dG/dT has a part the factorized matrix leaves out where k or Q depends on T.
  nonsymmetric_ = spec_.source.depends_on_temperature();
  for (const MaterialModel& m : model.materials())
    nonsymmetric_ = nonsymmetric_ || !m.spec->conductivity.is_constant();
  linear_ = !nonsymmetric_;
  for (const MaterialModel& m : model.materials())
    if (spec_.transient)
      linear_ = linear_ && m.spec->density.is_constant() && m.spec->specific_heat.is_constant();
  for (const auto& b : spec_.boundary)
    if (b.kind == HeatBoundarySpec::Kind::radiation ||
        (b.kind == HeatBoundarySpec::Kind::convection && !b.value.is_constant()))
      linear_ = false;
}

HeatSolver::~HeatSolver() = default;

void HeatSolver::start() {
  // The solution at t = 0: the initial temperature, or the steady one at t = 0.
  const Model& model = model_;
  const double T_ref = model.reference_temperature();
  mem_.R_last.assign(model.mesh().n_nodes(), 0.0);
  mem_.S_last.assign(model.mesh().n_nodes(), 0.0);
  HeatSnapshot s0;
  s0.time = 0;
  s0.T.resize(model.mesh().n_nodes());
  for (int n = 0; n < model.mesh().n_nodes(); ++n) {
    const Vec3& x = model.mesh().x[n];
    s0.T[n] =
        spec_.initial ? spec_.initial->eval_checked(x.x(), x.y(), x.z(), 0, "initial") : T_ref;
  }
  s0.flow.assign(spec_.boundary.size(), 0.0);
  s0.energy.assign(spec_.boundary.size(), 0.0);
  const ScopedTimer timer(seconds_);
  if (spec_.transient) {
    if (spec_.fixed_from_start) fixed_temperatures(0.0, s0.T);
    Evaluation ev;
    evaluate(s0.T, s0, 0.0, false, ev);
    mem_.R_last = std::move(ev.R);
    mem_.S_last = std::move(ev.SR);
    natural_flows(s0.T, 0.0, s0.flow_now);
    mem_.snapshots.push_back(std::move(s0));
  } else {
    HeatSnapshot steady;
    std::string why;
    if (!solve(s0, 0.0, steady, why))
      throw HeatDivergence("heat: the steady temperature at t = 0 did not converge: " + why);
    mem_.snapshots.push_back(std::move(steady));
  }
}

void HeatSolver::fixed_temperatures(double t, std::vector<double>& T) const {
  const auto& fixed = model_.heat_fixed();
  for (std::size_t n = 0; n < fixed.size(); ++n)
    if (fixed[n] >= 0) {
      const Vec3& x = model_.mesh().x[n];
      T[n] = spec_.boundary[fixed[n]].value.eval_checked(x.x(), x.y(), x.z(), t, "temperature");
    }
}

bool HeatSolver::solve(const HeatSnapshot& from, double t1, HeatSnapshot& to, std::string& why) {
  const auto& eq = model_.heat_dofs().eq;
  const int n_free = model_.heat_dofs().n_free;
  const bool transient = spec_.transient;
  const double dt = t1 - from.time;
  to.time = t1;
  to.T = from.T;
  fixed_temperatures(t1, to.T);
  Evaluation ev;
  std::vector<double> rhs(n_free), dT(n_free);
  double r_first = 0, s_first = 0, last_correction = INFINITY, t_scale = 1.0;
  for (int it = 0;; ++it) {
    // A linear problem keeps its factor while Δt and θ do.
    const double key = transient ? dt * (2 - theta_) : 0.0;  // one number for (Δt, θ ∈ [½, 1])
    const bool matrix = !linear_ || factored_dt_ != key;
    evaluate(to.T, from, t1, matrix && n_free > 0, ev);
    const double g = norm(model_.layout(), ev.G, eq), s = norm(model_.layout(), ev.S, eq);
    // Against the terms' magnitudes, at least those of the step's first iterate: where the
    // answer is T = 0 (a steady step whose temperatures ramp from 0, at t = 0) the magnitudes
    // vanish with the residual, and an inexact linear solve (CG) leaves g/s where it is.
    if (it == 0) s_first = s;
    const double s_ref = std::max(s, s_first);
    const double r = s_ref > 0 ? g / s_ref : 0.0;
    if (!std::isfinite(r)) {
      why = fmt::format("the temperatures are no longer finite numbers after {} iterations", it);
      return false;
    }
    // Every step takes at least one Newton step: a step whose temperatures barely change
    // starts with a residual that is small against the magnitudes of its terms, and taking it
    // as converged would freeze the temperatures (a slow approach to a steady state). A
    // nonlinear step also needs its last correction small against the temperatures' range.
    const bool stepped =
        it > 0 &&
        (linear_ && !nonsymmetric_ ? true : last_correction <= 10 * spec_.tolerance * t_scale);
    if ((r <= spec_.tolerance && stepped) || n_free == 0) {
      mem_.iterations += it;
      last_iterations_ = it;
      last_residual_ = r;
      step_flows(from, ev, to);
      mem_.R_last = std::move(ev.R);
      mem_.S_last = std::move(ev.SR);
      return true;
    }
    if (it == 0) r_first = r;
    if (it >= spec_.max_iterations || (it > 2 && r > 1e6 * r_first)) {
      why = fmt::format("no convergence in {} Newton iterations (relative residual {:.2e})", it, r);
      return false;
    }
    try {
      if (matrix) {
        system_->factorize();
        if (linear_) factored_dt_ = key;
      }
      for (std::size_t n = 0; n < eq.size(); ++n)
        if (eq[n] >= 0) rhs[eq[n]] = -ev.G[n];
      system_->solve(rhs, dT);
      // The whole Newton step, to a relative residual that falls with G's (quadratic
      // convergence) but need not go below a tenth of the tolerance.
      if (nonsymmetric_ && !full_newton_step(to.T, from, t1, rhs, dT,
                                             std::clamp(0.1 * r, 0.1 * spec_.tolerance, 1e-2))) {
        why = "the Newton step's linear solve (GMRES) did not converge";
        return false;
      }
    } catch (const LinearSystemError& e) {
      factored_dt_ = -1;
      why = e.what();
      return false;
    }
    last_correction = 0;
    t_scale = 1.0;  // K (or °C): the temperatures' distance from T_ref, at least one degree
    for (std::size_t n = 0; n < eq.size(); ++n) {
      if (eq[n] >= 0) {
        to.T[n] += dT[eq[n]];
        last_correction = std::max(last_correction, std::abs(dT[eq[n]]));
      }
      t_scale = std::max(t_scale, std::abs(to.T[n] - model_.reference_temperature()));
    }
    last_correction = model_.layout().largest(last_correction);
    t_scale = model_.layout().largest(t_scale);
  }
}

void HeatSolver::step_flows(const HeatSnapshot& from, const Evaluation& ev,
                            HeatSnapshot& to) const {
  const double t1 = to.time, dt = t1 - from.time;
  natural_flows(to.T, t1, to.flow_now);
  const double theta = spec_.transient ? theta_ : 1.0;
  const std::vector<double>& q0 = mem_.snapshots.empty() ? to.flow_now : from.flow_now;
  to.flow.assign(spec_.boundary.size(), 0.0);
  for (std::size_t b = 0; b < spec_.boundary.size(); ++b)
    to.flow[b] = theta * to.flow_now[b] + (1 - theta) * q0[b];
  // The reactions of the fixed temperatures, each node once: on a distributed mesh, each
  // rank adds its own nodes' and the ranks' shares are summed (root's holds the rest).
  const NodalLayout& layout = model_.layout();
  const bool parts = layout.kind() == NodalLayout::Kind::distributed;
  if (parts && !par::root()) std::fill(to.flow.begin(), to.flow.end(), 0.0);
  const auto& fixed = model_.heat_fixed();
  const std::size_t own = layout.owned_entries(fixed.size(), 1, static_cast<int>(fixed.size()));
  for (std::size_t n = 0; n < own; ++n)
    if (fixed[n] >= 0) to.flow[fixed[n]] += ev.G[n];
  layout.total(to.flow);
  to.energy = from.energy;
  to.energy.resize(to.flow.size(), 0.0);
  for (std::size_t b = 0; b < to.flow.size(); ++b) to.energy[b] += to.flow[b] * dt;
}

bool HeatSolver::full_newton_step(const std::vector<double>& T, const HeatSnapshot& from,
                                  double t1, const std::vector<double>& b, std::vector<double>& x,
                                  double rtol) {
  // GMRES on dG/dT P⁻¹ y = b, x = x0 + P⁻¹ y, from x0 = P⁻¹ b (the step of the symmetric
  // part): the preconditioned operator is the identity plus what P leaves out, so that a few
  // iterations do.
  const auto& eq = model_.heat_dofs().eq;
  const std::size_t nn = eq.size();
  std::vector<double> full(nn), Jv(nn);
  const LinearOperator apply = [&](const std::vector<double>& z, std::vector<double>& out) {
    for (std::size_t i = 0; i < nn; ++i) full[i] = eq[i] >= 0 ? z[eq[i]] : 0.0;
    jacobian_times(T, from, t1, full, Jv);
    for (std::size_t i = 0; i < nn; ++i)
      if (eq[i] >= 0) out[eq[i]] = Jv[i];
  };
  const LinearOperator precondition = [&](const std::vector<double>& v, std::vector<double>& z) {
    system_->solve(v, z);
  };
  // Over this rank's own free dofs (their prefix), summed over the ranks of a distributed
  // mesh; a replicated mesh's vectors are whole on every rank.
  const std::size_t own_free = static_cast<std::size_t>(model_.layout().owned_free(eq, 1));
  const InnerProduct dot = [&](const std::vector<double>& u, const std::vector<double>& w) {
    return model_.layout().dot(u, w, own_free);
  };
  GmresOptions options;
  options.rtol = rtol;
  options.restart = 30;
  options.max_cycles = 3;
  return gmres(apply, precondition, dot, b, x, options, mem_.gmres_iterations);
}

void HeatSolver::advance(double target) {
  const ScopedTimer timer(seconds_);
  const bool own = !spec_.times.empty();
  const double t_end = own ? spec_.times[std::min(next_target_, spec_.times.size() - 1)] : target;
  HENCKY_VERIFY(!own || next_target_ < spec_.times.size(),
                "heat: asked for a time after its last step");
  auto& snapshots = mem_.snapshots;
  // Targets to reach, each with its cut-back depth (as the mechanical step control).
  std::vector<std::pair<double, int>> targets = {{t_end, 0}};
  // Crank–Nicolson (θ < 1) starts with two backward-Euler half steps (Rannacher, Numer. Math.
  // 43, 1984): θ near ½ damps hardly at all the oscillation that initial temperatures which do
  // not meet the boundary conditions (a sudden surface temperature) leave, and it costs its
  // order; a fixed number of first-order steps at the start keeps the second order.
  const bool rannacher = spec_.transient && spec_.theta < 1 && mem_.steps == 0;
  if (rannacher) targets.push_back({0.5 * (snapshots.back().time + t_end), 0});
  theta_ = rannacher ? 1.0 : spec_.theta;
  while (!targets.empty()) {
    const auto [t1, depth] = targets.back();
    if (par::any(interrupt_requested()))
      throw Interrupted(fmt::format("interrupted in the heat step to t = {:g}", t1));
    HeatSnapshot to;
    std::string why;
    if (solve(snapshots.back(), t1, to, why)) {
      snapshots.push_back(std::move(to));
      targets.pop_back();
      ++mem_.steps;
      log_.info("heat {:4d}  t = {:<10.6g} iterations {:3d}  residual {:.2e}{}", mem_.steps, t1,
                last_iterations_, last_residual_,
                rannacher ? "  (Crank-Nicolson's backward-Euler start)" : "");
      continue;
    }
    const double t0 = snapshots.back().time, mid = 0.5 * (t0 + t1);
    if (depth >= model_.spec().solver.cutback || !(mid > t0 && mid < t1))
      throw HeatDivergence(
          fmt::format("heat: the step to t = {:g} did not converge after {} "
                      "cut-backs (the last to t = {:g}): {}",
                      t_end, depth, t1, why));
    log_.info("heat: step to t = {:g} failed ({}); cutting back to t = {:g}", t1, why, mid);
    targets.back().second = depth + 1;
    targets.push_back({mid, depth + 1});
  }
  theta_ = spec_.theta;
  if (own) ++next_target_;
}

void HeatSolver::interpolate(double t, std::vector<double>* T, std::vector<double>& flow,
                             std::vector<double>& energy) const {
  const auto& snapshots = mem_.snapshots;
  const double eps = 1e-12 * std::max(1.0, std::abs(t));
  std::size_t i = snapshots.size() - 1;
  while (i > 0 && snapshots[i - 1].time >= t - eps) --i;
  // snapshots[i] is the first at or after t.
  const HeatSnapshot& b = snapshots[i];
  if (std::abs(b.time - t) <= eps || i == 0) {
    HENCKY_VERIFY(!(b.time > t + eps), "heat: asked for a time before its snapshots");
    if (T) *T = b.T;
    flow = b.flow;
    energy = b.energy;
    return;
  }
  const HeatSnapshot& a = snapshots[i - 1];
  const double s = (t - a.time) / (b.time - a.time);
  auto lerp = [s](const std::vector<double>& u, const std::vector<double>& v,
                  std::vector<double>& out) {
    out.resize(v.size());
    for (std::size_t k = 0; k < v.size(); ++k) out[k] = u[k] + s * (v[k] - u[k]);
  };
  if (T) lerp(a.T, b.T, *T);
  lerp(a.flow, b.flow, flow);
  lerp(a.energy, b.energy, energy);
}

void HeatSolver::at(double t, std::vector<double>& T, std::vector<double>& flow) {
  if (mem_.snapshots.empty()) start();
  const double eps = 1e-12 * std::max(1.0, std::abs(t));
  while (mem_.snapshots.back().time < t - eps) advance(t);
  std::vector<double> energy;
  interpolate(t, &T, flow, energy);
  // A transient's flows: the mean over [committed, t], from the heat brought in, exact over
  // any grid of heat steps (the energy is linear in time within a heat step).
  const double t0 = mem_.committed;
  if (!spec_.transient || !(t > t0 + eps)) return;
  std::vector<double> flow0, energy0;
  interpolate(t0, nullptr, flow0, energy0);
  for (std::size_t k = 0; k < flow.size(); ++k) flow[k] = (energy[k] - energy0[k]) / (t - t0);
}

void HeatSolver::committed(double t) {
  const double eps = 1e-12 * std::max(1.0, std::abs(t));
  mem_.committed = t;
  auto& snapshots = mem_.snapshots;
  while (snapshots.size() > 1 && snapshots[1].time <= t + eps) snapshots.pop_front();
}

HeatMemory HeatSolver::memory() const { return mem_; }

void HeatSolver::resume(HeatMemory mem) {
  mem_ = std::move(mem);
  // The heat section's own steps after the newest solution: those of the case now (a restart
  // may change them).
  next_target_ = 0;
  if (!mem_.snapshots.empty()) {
    const double t = mem_.snapshots.back().time, eps = 1e-12 * std::max(1.0, std::abs(t));
    while (next_target_ < spec_.times.size() && spec_.times[next_target_] <= t + eps)
      ++next_target_;
  }
}

}  // namespace hencky
