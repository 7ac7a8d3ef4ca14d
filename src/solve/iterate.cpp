#include "solve/iterate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/timer.hpp"
#include "parallel/mpi.hpp"

namespace hencky {

IterateEvaluator::IterateEvaluator(const Model& m, const std::vector<char>* only,
                                   const Scheme& scheme, int max_flips, Log& log, Timings& timings,
                                   HeatSolver* heat)
    : m_(m),
      log_(log),
      timings_(timings),
      heat_(heat),
      points_(m, only, scheme),
      contact_(m, max_flips),
      layout_(m.layout()),
      own_dofs_(layout_.owned_entries(m.dofs().eq.size(), 3, m.mesh().n_nodes())),
      own_free_(layout_.owned_free(m.dofs().eq, 3)),
      updated_(m.spec().solver.updated_geometry),
      x_(m.mesh().x) {}

double IterateEvaluator::norm(const std::vector<double>& v) const {
  return std::sqrt(layout_.dot(v, v, own_dofs_));
}

double IterateEvaluator::correction_ratio(const State& c, const State& trial,
                                          const std::vector<double>& u_before) const {
  std::vector<double> d(trial.u.size()), du(trial.u.size());
  for (std::size_t i = 0; i < d.size(); ++i) {
    d[i] = trial.u[i] - u_before[i];
    du[i] = trial.u[i] - c.u[i];
  }
  const double step = norm(du), last = norm(d);
  return step > 0 ? last / step : 0.0;
}

double IterateEvaluator::step_force(const State& c, const State& trial,
                                    const Evaluation& ev) const {
  return std::max({norm(trial.f_ext), norm(c.f_int), norm(trial.f_int), std::sqrt(ev.r_loads2)});
}

void IterateEvaluator::temperatures_only(const State& c, double t1, State& trial) {
  trial = c;
  trial.time = t1;
  {
    ScopedTimer timer(timings_.heat);
    heat_->at(t1, trial.nodal_temperature, trial.heat_flow);
  }
  points_.temperatures(trial, log_);
}

void IterateEvaluator::begin(const State& c, double t1, State& trial) {
  const auto& dofs = m_.dofs();
  trial.time = t1;
  trial.u = c.u;
  if (heat_) {
    ScopedTimer timer(timings_.heat);
    heat_->at(t1, trial.nodal_temperature, trial.heat_flow);
  } else {
    m_.nodal_temperature(t1, trial.nodal_temperature);
  }
  points_.temperatures(trial, log_);
  m_.prescribed_displacement(t1, trial.u);  // prescribed entries of u at t1, free ones at t
  if (updated_) {
    for (int n = 0; n < m_.mesh().n_nodes(); ++n)
      x_[n] = m_.mesh().x[n] + Vec3(c.u[3 * n], c.u[3 * n + 1], c.u[3 * n + 2]);
    points_.set_configuration(x_);
  }
  m_.external_forces(t1, trial.f_ext, updated_ ? &x_ : nullptr);
  if (m_.has_plasticity()) points_.begin_step(c, trial);
  if (contact_.active()) contact_.begin(c, trial);
  // Equilibrium target of the step, (2.29)-(2.30). The step's equation is written on x_:
  //   F_int − ∫Bᵀσ(t) = P(t+Δt) − P(t) + ΔF_contact + γ·R(t),
  // with P and ∫Bᵀσ(t) on x_ and R(t) = ⁽ᵗ⁾P + ⁽ᵗ⁾F_contact − ∫Bᵀσ(t), the defect the previous
  // step left: on the configuration of the step before, as that step computed it (2.30; the
  // state keeps f_ext and f_int as their step computed them), or on x_ (2.31,
  // correction_form: current). The iterate's F_int (PointPass::update) is ∫F S ∇N dx on
  // x_, the internal force of σ(t+Δt) on its own configuration pulled back to x_. On
  // the undeformed mesh both forms are c's own figures and the target is
  // F(t+Δt) − (1 − γ)·R(t): with γ = 1 the defect is corrected in full. The supports' forces
  // of the step are part of the residual (residual_vector), so that R(t) carries ⁽ᵗ⁾F as
  // (3.6) asks.
  const double gamma = correction(t1);
  const std::vector<double>* loads = &c.f_ext;  // P(t) and ∫Bᵀσ(t) on x_
  const std::vector<double>* forces = &c.f_int;
  if (updated_) {
    m_.external_forces(c.time, loads_at_t_, &x_);
    points_.internal_forces(c, x_, forces_at_t_);
    loads = &loads_at_t_;
    forces = &forces_at_t_;
    report_defect(c);
  }
  const bool current = m_.spec().solver.correction_current;
  const std::vector<double>& loads_r = current ? *loads : c.f_ext;  // those of R(t)
  const std::vector<double>& forces_r = current ? *forces : c.f_int;
  target_.resize(dofs.n_dofs());
  // On the undeformed mesh loads == c.f_ext and forces == c.f_int: the general form reduces to
  // the second, which is kept as written so that small-geometry results stay bit for bit.
  for (int i = 0; i < dofs.n_dofs(); ++i)
    target_[i] = updated_
                     ? trial.f_ext[i] - ((*loads)[i] + c.f_contact[i] - (*forces)[i]) +
                           gamma * (loads_r[i] + c.f_contact[i] - forces_r[i])
                     : trial.f_ext[i] - (1 - gamma) * (c.f_ext[i] + c.f_contact[i] - c.f_int[i]);
  rhs_.resize(dofs.n_free);
}

/// Under `geometry: updated`, the log's figure of the equilibrium defect of σ(t) on the
/// configuration reached at t, ‖P(t) + F_contact(t) − ∫Bᵀσ(t)‖ over x_ on the free dofs: what
/// the step before left (the residual (2.31) corrects), against the larger of the loads and
/// those internal forces (the supports' included).
void IterateEvaluator::report_defect(const State& c) const {
  const auto& dofs = m_.dofs();
  double d2 = 0;
  for (std::size_t i = 0; i < own_dofs_; ++i)
    if (dofs.eq[i] >= 0) {
      const double d = loads_at_t_[i] + c.f_contact[i] - forces_at_t_[i];
      d2 += d * d;
    }
  d2 = layout_.total(d2);
  const double scale = std::max(norm(loads_at_t_), norm(forces_at_t_));
  log_.detail("  equilibrium defect at t = {:g} on its configuration: {:.3e} ({:.3e} relative)",
              c.time, std::sqrt(d2), scale > 0 ? std::sqrt(d2) / scale : 0.0);
}

/// γ of the step that ends at t1 (solver.correction, checked at the planned steps' times when
/// the case was read; a cut-back's time between them is checked here).
double IterateEvaluator::correction(double t1) const {
  const Expression& g = m_.spec().solver.correction;
  const double v = g.eval_checked(0, 0, 0, t1, "the correction γ");
  if (v < 0)
    throw InputError(g.where(), fmt::format("the correction γ = '{}' is {:g} at t = {:g} (a step "
                                            "cut back): expected >= 0 at every step",
                                            g.text(), v, t1));
  return v;
}

Evaluation IterateEvaluator::evaluate(const State& c, State& trial, bool update_contact,
                                      PointMode mode) {
  Evaluation ev;
  {
    ScopedTimer timer(timings_.material);
    ev.points = points_.update(c, trial, x_, mode);
  }
  if (const Model::CellFacts e = m_.cell_facts(ev.points.inverted_cell); e.tag >= 0)
    throw SolveError(fmt::format(
        "element {} is turned inside out at t = {:g} or halfway through the step to t = {:g} "
        "(geometry: updated): the step moved its nodes past each other (or, in an 8-node "
        "hexahedron or a wedge, compressed a direction of a point to nothing); smaller steps "
        "may follow the deformation, a mesh this distorted will not",
        e.tag, c.time, trial.time));
  negative_secant_cell_ = ev.points.negative_secant_cell;
  if (update_contact)
    this->update_contact(c, trial, ev);
  else
    ev.r2 = residual_vector(trial, &ev.r_loads2);
  return ev;
}

void IterateEvaluator::update_contact(const State& c, State& trial, Evaluation& ev) {
  if (contact_.active()) {
    ScopedTimer timer(timings_.contact);
    contact_.update(c, trial);
  }
  ev.r2 = residual_vector(trial, &ev.r_loads2);
}

double IterateEvaluator::residual_vector(State& trial, double* loads2) {
  const auto& dofs = m_.dofs();
  if (contact_.active()) {
    ScopedTimer timer(timings_.contact);
    contact_.forces(trial);
  }
  double r2 = 0, l2 = 0;
  for (int i = 0; i < dofs.n_dofs(); ++i)
    if (int k = dofs.eq[i]; k >= 0) {
      const double loads = target_[i] - trial.f_int[i];
      rhs_[k] = loads + trial.f_contact[i];
      if (static_cast<std::size_t>(i) >= own_dofs_) continue;  // a ghost: its owner counts it
      r2 += rhs_[k] * rhs_[k];
      l2 += loads * loads;
    }
  if (layout_.kind() == NodalLayout::Kind::distributed) {
    double sums[2] = {r2, l2};
    par::sum_in_place(std::span<double>(sums));
    r2 = sums[0], l2 = sums[1];
  }
  if (loads2) *loads2 = l2;
  return r2;
}

double IterateEvaluator::equilibrium_defect(const State& s) const {
  double r = 0;
  for (std::size_t i = 0; i < own_dofs_; ++i)
    if (m_.dofs().eq[i] >= 0) {
      const double d = s.f_ext[i] + s.f_contact[i] - s.f_int[i];
      r += d * d;
    }
  return std::sqrt(layout_.total(r));
}

}  // namespace hencky
