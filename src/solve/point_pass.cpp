#include "solve/point_pass.hpp"

#include <fmt/format.h>

#include <array>
#include <atomic>
#include <climits>
#include <cmath>
#include <cstring>

#include "fem/hencky_strain.hpp"
#include "fem/reference_element.hpp"
#include "parallel/mpi.hpp"
#include "solve/element_matrix.hpp"

namespace hencky {

PointPass::PointPass(const Model& m, const std::vector<char>* only, const Scheme& scheme)
    : m_(m), only_(only), plastic_(m.has_plasticity()), scheme_(scheme) {
  const bool updated = m.spec().solver.updated_geometry;
  if (plastic_ || updated) point_volumes(m_, m.mesh().x, point_volume_);
  if (updated) start_volume_ratio_.assign(m.n_points(), 1.0);
  if (!plastic_) return;
  const int n = m.n_points();
  point_step_.resize(n);
  point_iter_.resize(n);
  tangent_.assign(n, Tangent{});
  defect_sigma_.assign(n, 0.0);
  defect_eps_.assign(n, 0.0);
  excess_.assign(n, -INFINITY);
}

/// The volume weight dv = det J·w of every point of this rank's cells on the configuration x.
void PointPass::point_volumes(const Model& m, const std::vector<Vec3>& config,
                              std::vector<double>& v) {
  v.assign(m.n_points(), 0.0);
  const auto& mesh = m.mesh();
  CellKinematics kin;
  Vec3 x[max_cell_nodes];
  for (int e = 0; e < mesh.cells.size(); ++e) {
    if (!m.holds_points(e)) continue;
    const auto nodes = mesh.cells.nodes(e);
    for (std::size_t a = 0; a < nodes.size(); ++a) x[a] = config[nodes[a]];
    kin.compute(reference_table(mesh.cells.type[e]), std::span<const Vec3>(x, nodes.size()));
    for (int q = 0; q < kin.points; ++q) v[m.point_offset(e) + q] = kin.dv[q];
  }
}

void PointPass::set_configuration(const std::vector<Vec3>& x) {
  if (start_volume_ratio_.empty()) return;
  point_volumes(m_, x, start_volume_ratio_);
  for (std::size_t p = 0; p < start_volume_ratio_.size(); ++p)
    if (point_volume_[p] > 0) start_volume_ratio_[p] /= point_volume_[p];
}

Voigt PointPass::start_stress(const State& c, int p) const {
  return start_volume_ratio_.empty() ? c.stress[p] : Voigt(start_volume_ratio_[p] * c.stress[p]);
}

void PointPass::temperatures(State& s, Log& log) const {
  const auto& mesh = m_.mesh();
  s.temperature.resize(m_.n_points());
  s.constants.resize(m_.n_points());
  const int n_mat = static_cast<int>(m_.materials().size());
  std::vector<double> t_min(n_mat, INFINITY), t_max(n_mat, -INFINITY);
  int bad_cell = -1;  // the first cell with a temperature whose thermal strain overflows
  double bad_T = 0;
  const bool linear_temperature = m_.spec().temperature.linear_in_quadratic_cells;
  for (int e = 0; e < mesh.cells.size(); ++e) {
    if (!m_.holds_points(e)) continue;
    const auto nodes = mesh.cells.nodes(e);
    const auto& tab = reference_table(mesh.cells.type[e]);
    const auto& mat = m_.material_of(e);
    const int mi = m_.material_index(e);
    // temperature.interpolation: linear, in a quadratic cell: ccx's weights of the nodes'
    // temperatures (ReferenceTable::N_linear_temperature).
    const bool as_ccx = linear_temperature && !tab.N_linear_temperature.empty();
    for (int q = 0; q < tab.n_points; ++q) {
      const double* N =
          &(as_ccx ? tab.N_linear_temperature : tab.N)[static_cast<std::size_t>(q) * tab.n_nodes];
      double T = 0;
      for (std::size_t a = 0; a < nodes.size(); ++a) T += N[a] * s.nodal_temperature[nodes[a]];
      const int p = m_.point_offset(e) + q;
      s.temperature[p] = T;
      s.constants[p] = mat.at(T);
      if (bad_cell < 0 && !m_.thermal_in_range(mi, s.constants[p], T)) bad_cell = e, bad_T = T;
      t_min[mi] = std::min(t_min[mi], T);
      t_max[mi] = std::max(t_max[mi], T);
    }
  }
  // An input error, before the step is solved; every rank reports the model's first such cell.
  if (const int cell = m_.agreed_cell(bad_cell); cell >= 0) {
    double T = bad_cell >= 0 && m_.agreed_index(bad_cell) == cell ? bad_T : -INFINITY;
    par::max_in_place(std::span<double>(&T, 1));
    m_.thermal_out_of_range(m_.cell_facts(cell), T, s.time);
  }
  par::min_in_place(std::span<double>(t_min));
  par::max_in_place(std::span<double>(t_max));
  for (int k = 0; k < n_mat; ++k)
    if (t_min[k] <= t_max[k]) m_.materials()[k].warn_outside(t_min[k], t_max[k], log);
}

/// The law's state of point p at t and at the iterate (empty spans without internal variables).
LawState PointPass::law_state(const State& c, State& trial, int p) const {
  const std::size_t n = m_.law_state_size(), at = static_cast<std::size_t>(p) * n;
  if (n == 0) return {};
  return {std::span<const double>(c.internal).subspan(at, n),
          std::span<double>(trial.internal).subspan(at, n)};
}

/// A plastic point whose iterate is elastic (the elastic start): its plastic state is that of
/// t, and the scheme's memory starts again.
void PointPass::keep_plastic_state(const State& c, State& trial, int p) {
  const LawState s = law_state(c, trial, p);
  std::copy(s.at_t.begin(), s.at_t.end(), s.now.begin());
  trial.plastic_strain[p] = c.plastic_strain[p];
  trial.eps_p_eq[p] = c.eps_p_eq[p];
  trial.eps_ep[p] = c.eps_ep[p];
  trial.eps_ep_max[p] = c.eps_ep_max[p];
  trial.flowing[p] = 0;
  defect_sigma_[p] = defect_eps_[p] = 0;
  point_iter_[p] = scheme_.start_iteration(point_step_[p]);
  // The elastic iterate counts as the step's first: the `-stiffness` schemes decide their
  // start slope at the next iterate only (start_slope_on_unloading), while the step loop may
  // still factorize their matrix again (StepMatrix::needs_elements). Counted from 0, a point
  // could switch to 3G one iterate later, with the matrix kept at its loading slope.
  point_iter_[p].k = 1;
}

/// The plastic state of point p at the iterate from the scheme's update u (its stress, τ under
/// `updated`, and its plastic increment).
void PointPass::take_plastic_update(const State& c, State& trial, int p, const PointUpdate& u) {
  trial.stress[p] = u.sigma;
  trial.plastic_strain[p] = c.plastic_strain[p] + u.d_lambda * u.z;
  trial.eps_p_eq[p] = std::max(0.0, c.eps_p_eq[p] + u.d_lambda);
  trial.eps_ep[p] = u.eps_ep;
  trial.eps_ep_max[p] = std::max(c.eps_ep_max[p], u.eps_ep);
  trial.flowing[p] = u.plastic;
  defect_sigma_[p] = u.defect_sigma;
  defect_eps_[p] = u.defect_eps;
}

/// The scheme's update of plastic point p for the strain increment d_eps of the iterate (the
/// point law, or the scheme's initial parameters): its memory and its plastic state kept.
PointUpdate PointPass::scheme_update(const State& c, State& trial, int p, const Voigt& sigma0,
                                     const Voigt& d_eps, PointMode mode) {
  const Voigt d_mech =
      d_eps - thermal_strain_increment(c.constants[p], c.temperature[p], trial.constants[p],
                                       trial.temperature[p], sigma0);
  PointUpdate u = mode == PointMode::initial
                      ? scheme_.evaluate_initial(trial.constants[p], point_step_[p], point_iter_[p],
                                                 sigma0, d_mech)
                      : scheme_.evaluate(trial.constants[p], point_step_[p], point_iter_[p], sigma0,
                                         d_mech, law_state(c, trial, p));
  point_iter_[p] = u.next;
  take_plastic_update(c, trial, p, u);
  return u;
}

/// Under `geometry: updated` the law's tensors turn with the material, as the plastic strain
/// does: R α Rᵀ for a stress-like tensor (the law works in the frame of the step's
/// configuration; its state at t+Δt is kept in the frame of the configuration there).
void PointPass::rotate_law_state(const PointLaw& law, const Mat3& r, State& trial, int p) const {
  std::size_t at = static_cast<std::size_t>(p) * m_.law_state_size();
  for (const LawVariable& v : law.variables()) {
    if (v.size == 6) {
      Eigen::Map<Voigt> t(trial.internal.data() + at);
      t = rotate_stress(r, t);
    }
    at += v.size;
  }
}

/// Per point, what stays fixed during the step (flow direction, start slope, the curve at
/// t+Δt) and the scheme's initial parameters.
void PointPass::begin_step(const State& c, const State& trial) {
  const auto& mesh = m_.mesh();
  const int n_cells = mesh.cells.size();
#pragma omp parallel for schedule(static) if (n_cells > 4000)
  for (int e = 0; e < n_cells; ++e) {
    const auto& mat = m_.material_of(e);
    if (!mat.plastic() || !mine(e)) continue;
    for (int p = m_.point_offset(e); p < m_.point_offset(e + 1); ++p) {
      PointAtT at;
      at.sigma = start_stress(c, p);
      at.eps_p = c.eps_p_eq[p];
      at.eps_ep = c.eps_ep[p];
      at.eps_ep_max = c.eps_ep_max[p];
      at.flowing = c.flowing[p] != 0;
      point_step_[p] =
          scheme_.begin_point_step(trial.constants[p], *mat.law, *mat.hardening,
                                   trial.temperature[p], mat.elastic_unloading, at, point_iter_[p]);
    }
  }
}

/// Point update and internal forces. Elastic materials: σ = σ(t) + D(t+Δt)(Δε − Δε^th),
/// (1.9), (1.12). Plastic ones: the scheme's point law (solve/schemes.hpp).
/// Under `geometry: updated` x is the configuration at t and the step is the updated
/// Lagrangian one of CellDeformation (src/fem/geometry.hpp) on Hencky's strain (HenckyStep,
/// src/fem/hencky_strain.hpp): the point law takes the increment of the elastic logarithmic
/// strain of the exponential map for Δε and the Kirchhoff stress τ(t) = J(t)σ(t) for its
/// start, in the frame of x, and returns τ; the step's forces are those of
/// S = U⁻¹τU⁻¹/J(t), the stress kept is the Cauchy stress J⁻¹FSFᵀ = RτRᵀ/J, and the plastic
/// strain and the law's tensors turn with R. The step's flow direction Z of τ(t) stays valid:
/// the law works in the frame of x.
PointPassResult PointPass::update(const State& c, State& trial, const std::vector<Vec3>& config,
                                  PointMode mode) {
  const bool elastic = mode == PointMode::elastic;
  const auto& mesh = m_.mesh();
  const bool updated = m_.spec().solver.updated_geometry;
  trial.f_int.assign(m_.dofs().n_dofs(), 0.0);
  std::atomic<bool> changed{false};
  std::atomic<int> undefined_cell{-1}, negative_secant_cell{-1}, inverted_cell{-1};
  // The point's matrix for the next solve; a change is what makes the step loop assemble again.
  auto set_tangent = [&](int p, const Tangent& t) {
    if (tangent_[p] == t) return;
    tangent_[p] = t;
    changed.store(true, std::memory_order_relaxed);
  };
  // The first cell to raise a flag names it.
  auto flag = [](std::atomic<int>& cell, int e) {
    int none = -1;
    cell.compare_exchange_strong(none, e);
  };
  m_.assembler().vector(
      [&](int e, CellBuffers& b) {
        const auto nodes = mesh.cells.nodes(e);
        const int n = static_cast<int>(nodes.size());
        const MaterialModel& mat = m_.material_of(e);
        const bool plastic = mat.plastic();
        Vec3 x[max_cell_nodes];
        double du[3 * max_cell_nodes];
        for (int a = 0; a < n; ++a) {
          x[a] = config[nodes[a]];
          for (int d = 0; d < 3; ++d)
            du[3 * a + d] = trial.u[3 * nodes[a] + d] - c.u[3 * nodes[a] + d];
        }
        const ReferenceTable& table = reference_table(mesh.cells.type[e]);
        CellKinematics& kin = thread_kinematics();
        kin.compute(table, std::span<const Vec3>(x, n));
        CellDeformation& def = thread_deformation();
        // A cell turned inside out by the iterate has no strain: the step fails
        // (IterateEvaluator::evaluate) and is cut back. The undeformed mesh was checked when the
        // model was made, and each step's start is a converged iterate.
        if (updated && !(def.compute(kin, du) > 0)) return flag(inverted_cell, e);
        HenckyStep hencky;
        for (int q = 0; q < kin.points; ++q) {
          const int p = m_.point_offset(e) + q;
          // Under `updated` the law works on Hencky's strain and the Kirchhoff stress τ = Jσ.
          const Voigt sigma0 = start_stress(c, p);
          if (updated) hencky.start(c.constants[p].compliance() * sigma0);
          const Voigt d_eps = updated ? hencky.increment(def.E[q]) : kin.strain(q, du);
          if (!plastic || elastic) {
            trial.stress[p] =
                elastic_stress_update(c.constants[p], c.temperature[p], trial.constants[p],
                                      trial.temperature[p], sigma0, d_eps);
            if (plastic) {
              keep_plastic_state(c, trial, p);
              set_tangent(p, Tangent{});  // the elastic matrix
            }
          } else {
            const PointUpdate u = scheme_update(c, trial, p, sigma0, d_eps, mode);
            if (u.undefined) flag(undefined_cell, e);
            if (u.negative_secant) flag(negative_secant_cell, e);
            set_tangent(p, u.tangent);
          }
          if (plastic) measure_excess(mat, c, trial, p, trial.stress[p]);
          if (updated) {
            const Voigt S = hencky.second_piola(trial.stress[p], start_volume_ratio_[p]);
            def.add_force(kin, q, S, kin.dv[q], b.fe);
            // σ = RτRᵀ/J with J = J(t)·det F, so that the next step's τ(t) = Jσ is the law's τ.
            // It is J⁻¹FSFᵀ, but in a B-bar cell, whose S is that of C̄ and not of C.
            const Mat3 r = def.rotation(q);
            trial.stress[p] =
                rotate_stress(r, trial.stress[p]) / (start_volume_ratio_[p] * def.J[q]);
            if (plastic) {
              trial.plastic_strain[p] = rotate_strain(r, trial.plastic_strain[p]);
              rotate_law_state(*mat.law, r, trial, p);
            }
          } else {
            kin.add_bt_sigma(q, trial.stress[p], kin.dv[q], b.fe);
          }
        }
      },
      trial.f_int, only_);
  // Every rank takes the same decisions: the flags and the failing cells over all ranks.
  PointPassResult r;
  r.undefined_cell = m_.agreed_cell(undefined_cell.load());
  r.negative_secant_cell = m_.agreed_cell(negative_secant_cell.load());
  r.inverted_cell = m_.agreed_cell(inverted_cell.load());
  r.tangent_changed = par::any(changed.load());
  m_.layout().sum(trial.f_int, 3);
  if (plastic_) measures(trial, r);
  return r;
}

void PointPass::internal_forces(const State& s, const std::vector<Vec3>& config,
                                std::vector<double>& f) const {
  const auto& mesh = m_.mesh();
  f.assign(m_.dofs().n_dofs(), 0.0);
  m_.assembler().vector(
      [&](int e, CellBuffers& b) {
        const auto nodes = mesh.cells.nodes(e);
        const int n = static_cast<int>(nodes.size());
        Vec3 x[max_cell_nodes];
        for (int a = 0; a < n; ++a) x[a] = config[nodes[a]];
        CellKinematics& kin = thread_kinematics();
        kin.compute(reference_table(mesh.cells.type[e]), std::span<const Vec3>(x, n));
        for (int q = 0; q < kin.points; ++q)
          kin.add_bt_sigma(q, s.stress[m_.point_offset(e) + q], kin.dv[q], b.fe);
      },
      f, only_);
  m_.layout().sum(f, 3);
}

void PointPass::initial_strains(std::vector<double>& e0) const {
  e0.clear();
  for_plastic_points([&](int p) {
    const Voigt& v = point_iter_[p].e0;
    e0.insert(e0.end(), v.data(), v.data() + 6);
  });
}

void PointPass::plastic_point_weights(std::vector<double>& weight) const {
  weight.clear();
  for_plastic_points([&](int p) {
    // Δε^0 is deviatoric (along flow directions): Δε^0ᵀDΔε^0 = 2G Σ ε_ii² + G Σ γ_ij²
    const double g = point_volume_[p] * point_step_[p].curve.three_g / 3;
    for (int i = 0; i < 6; ++i) weight.push_back(i < 3 ? 2 * g : g);
  });
}

void PointPass::set_initial_strains(std::span<const double> e0) {
  std::size_t i = 0;
  for_plastic_points([&](int p) {
    for (int j = 0; j < 6; ++j) point_iter_[p].e0[j] = e0[i++];
  });
}

int PointPass::hold_plastic_set() {
  int n = 0;
  for_plastic_points([&](int p) {
    PointIteration& it = point_iter_[p];
    it.held = !point_step_[p].curve.elastic_unloading ? 0 : it.plastic_prev ? 1 : -1;
    it.breaks_hold = false;
    n += it.held > 0;
  });
  return static_cast<int>(par::sum(static_cast<long long>(n)));
}

void PointPass::move_broken_holds() {
  for_plastic_points([&](int p) {
    PointIteration& it = point_iter_[p];
    if (it.breaks_hold) it.held = static_cast<signed char>(-it.held);
    it.breaks_hold = false;
  });
}

void PointPass::free_plastic_set() {
  for_plastic_points([&](int p) { point_iter_[p].held = 0, point_iter_[p].breaks_hold = false; });
}

}  // namespace hencky
