#include "solve/analysis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cmath>
#include <deque>
#include <type_traits>

#include "fem/geometry.hpp"
#include "fem/reference_element.hpp"
#include "parallel/mpi.hpp"
#include "solve/anderson.hpp"
#include "solve/contact_step.hpp"
#include "solve/recovery.hpp"
#include "solve/schemes.hpp"

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
  StepSolver(const Model& m, LinearSystem& system, Log& log, Timings& timings)
      : m_(m), system_(system), log_(log), timings_(timings), contact_(m) {
    // On more than one rank each rank works on its own cells (only_) and the nodal vectors are
    // summed over the ranks.
    only_ = system.own_cells();
    // A rank stores the points of the cells it holds and works on its own cells: these must
    // agree (make_run_solver makes the model hold the partition's cells).
    for (int e = 0; e < m.mesh().cells.size(); ++e)
      if (mine(e) && !m.holds_points(e))
        throw std::logic_error("the model does not hold the points of this rank's cells");
    plastic_ = m.has_plasticity();
    options_.kind = scheme_from_name(m.spec().solver.scheme);
    options_.strain_form = m.spec().solver.curve_form == "strain";
    options_.omega = m.spec().solver.relaxation;
    // Not with contact: extrapolating a long step after short ones pushes the nodes near the
    // contact far into the surfaces (8 increments deep on a plastic indentation, where the
    // step then failed; from the converged state it took 10 iterations).
    extrapolate_ = plastic_ && options_.kind == SchemeKind::newton &&
                   m.spec().solver.extrapolate && m.contacts().empty();
    if (plastic_) {
      Vec3 lo = m.mesh().x.front(), hi = lo;
      for (const Vec3& p : m.mesh().x) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      model_size_ = (hi - lo).norm();
      const int n = m.n_points();
      point_step_.resize(n);
      point_iter_.resize(n);
      tangent_.assign(n, Tangent{});
      defect_sigma_.assign(n, 0.0);
      defect_eps_.assign(n, 0.0);
      point_volume_.assign(n, 0.0);
      const auto& mesh = m.mesh();
      CellKinematics kin;
      Vec3 x[max_cell_nodes];
      for (int e = 0; e < mesh.cells.size(); ++e) {
        if (!m.holds_points(e)) continue;
        const auto nodes = mesh.cells.nodes(e);
        for (std::size_t a = 0; a < nodes.size(); ++a) x[a] = mesh.x[nodes[a]];
        kin.compute(reference_table(mesh.cells.type[e]), std::span<const Vec3>(x, nodes.size()));
        for (int q = 0; q < kin.points; ++q) point_volume_[m.point_offset(e) + q] = kin.dv[q];
      }
    }
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
    s.plastic_strain.assign(n_pts, Voigt::Zero());
    s.eps_p_eq.assign(n_pts, 0.0);
    s.eps_ep.assign(n_pts, 0.0);
    s.eps_ep_max.assign(n_pts, 0.0);
    s.flowing.assign(n_pts, 0);
    contact_.initial(s);
    return s;
  }

  int factorizations() const { return factorizations_; }
  double delta_sigma() const { return delta_sigma_; }
  double delta_eps() const { return delta_eps_; }

  /// Warnings about the curves after a converged step: temperatures outside their tables,
  /// plastic strains beyond their last point. Collective.
  void check_curves(const State& s) const {
    if (!plastic_) return;
    const auto& mesh = m_.mesh();
    const int n_mat = static_cast<int>(m_.materials().size());
    std::vector<double> t_min(n_mat, INFINITY), t_max(n_mat, -INFINITY), e_max(n_mat, 0.0);
    for (int e = 0; e < mesh.cells.size(); ++e) {
      const int mi = m_.material_index(e);
      if (!m_.materials()[mi].plastic()) continue;
      for (int p = m_.point_offset(e); p < m_.point_offset(e + 1); ++p) {
        t_min[mi] = std::min(t_min[mi], s.temperature[p]);
        t_max[mi] = std::max(t_max[mi], s.temperature[p]);
        e_max[mi] = std::max(e_max[mi], s.eps_p_eq[p]);
      }
    }
    // Root warns for the whole model (the log is silent on the other ranks).
    par::min_in_place(std::span<double>(t_min));
    par::max_in_place(std::span<double>(t_max));
    par::max_in_place(std::span<double>(e_max));
    for (int k = 0; k < n_mat; ++k)
      if (const auto& mat = m_.materials()[k]; mat.plastic() && t_min[k] <= t_max[k])
        mat.hardening->warn_outside(mat.spec->name, t_min[k], t_max[k], e_max[k], log_);
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
    if (plastic_) begin_plastic_step(c, trial);
    if (contact_.active()) contact_.begin(c, trial);

    // Equilibrium target of the step, (2.29)-(2.30): F(t+Δt) − (1 − γ)·R(t), R(t) = F(t) +
    // F_contact(t) − F_int(t): with γ = 1 the defect left by the previous step is corrected in
    // full. The support's forces of the step are part of the residual (residual_vector), so
    // that R(t) carries ⁽ᵗ⁾F as (3.6) asks.
    const double gamma = spec.correction;
    target_.resize(dofs.n_dofs());
    for (int i = 0; i < dofs.n_dofs(); ++i)
      target_[i] = trial.f_ext[i] - (1 - gamma) * (c.f_ext[i] + c.f_contact[i] - c.f_int[i]);

    std::vector<double>& rhs = rhs_;
    rhs.resize(dofs.n_free);
    delta_.resize(dofs.n_free);
    // Force scale of the step, fixed at the predictor: the loads, the internal forces before and
    // after the predictor, and the predictor's residual (which carries thermal and prescribed-
    // displacement loading). A step whose answer has no load and no stress (free expansion,
    // unloading to zero) still has a scale, so round-off is recognised as convergence.
    double f_norm = 0, previous_residual = INFINITY;
    anderson_.reset();
    for (iterations = 0;; ++iterations) {
      update_points(c, trial);
      if (contact_.active() && iterations > 0) {
        // Report steps 3-4 with the iterate of the last solve.
        const auto t0 = Clock::now();
        contact_.update(c, trial);
        timings_.contact += seconds_since(t0);
      }
      double r_loads = 0;  // the residual without the supports' forces
      double r = residual_vector(trial, &r_loads);
      if (iterations == 0) {
        f_norm =
            std::max({norm(trial.f_ext), norm(c.f_int), norm(trial.f_int), std::sqrt(r_loads)});
        r = extrapolated_start(c, trial, r);
      }
      // With contact, the force a surface's travel puts on the first iterate (κ times the
      // travel) is no force scale of the problem: that of the internal forces of the iterate is.
      const double scale = contact_.active() ? std::max(f_norm, norm(trial.f_int)) : f_norm;
      residual = scale > 0 ? std::sqrt(r) / scale : 0.0;
      // A NaN or an infinity in the iterate makes r or the scale non-finite; a NaN scale would
      // read as "no load" above (and a residual of 0 as converged).
      if (!std::isfinite(r) || !std::isfinite(scale)) residual = NAN;
      if (only_) {
        // The sums over ranks may differ in their last bits from rank to rank: root's figures
        // decide for all.
        double d[3] = {residual, delta_sigma_, delta_eps_};
        par::broadcast(std::span<double>(d));
        residual = d[0], delta_sigma_ = d[1], delta_eps_ = d[2];
      }
      if (plastic_) {
        log_.detail(
            "  iteration {}: relative residual {:.3e}  Δσ {:.3e}  Δε {:.3e}  plastic "
            "points {}",
            iterations, residual, delta_sigma_, delta_eps_, plastic_points_);
      } else {
        log_.detail("  iteration {}: relative residual {:.3e}", iterations, residual);
      }
      if (contact_.active()) {
        const ContactProgress& cp = contact_.progress();
        log_.detail("    contact: {} nodes{}{}, largest |gap| {:.2e} of the allowed",
                    cp.in_contact, cp.set_changed ? ", set changed" : "",
                    cp.kappa_raised ? ", κ raised" : "", cp.worst_gap);
      }
      if (!std::isfinite(residual)) not_finite(trial, iterations, residual);
      const bool measures_ok =
          !plastic_ || (delta_sigma_ <= spec.tolerance && delta_eps_ <= spec.tolerance);
      const bool contact_ok = !contact_.active() || contact_.progress().converged();
      if (iterations >= 1 && residual <= spec.tolerance && measures_ok && contact_ok) {
        // The reported residual is the true equilibrium defect F − F_int (γ only shifts the
        // target).
        residual = scale > 0 ? equilibrium_defect(trial) / scale : 0.0;
        // Small strains: an equilibrium found with displacements of the order of the body is a
        // mechanism (a load at or above the plastic limit load), not an answer.
        if (plastic_) {
          double u_max = 0;
          for (int n = 0; n < m_.mesh().n_nodes(); ++n)
            u_max = std::max(u_max,
                             Vec3(trial.u[3 * n], trial.u[3 * n + 1], trial.u[3 * n + 2]).norm());
          if (u_max > spec.mechanism_limit * model_size_) {
            throw SolveError(fmt::format(
                "the displacement reached {:.3g}, more than {:g} % of the model's size {:.3g} "
                "(solver.mechanism_limit): the body has become a mechanism (the load is at or "
                "above the plastic limit load), which a small-strain analysis cannot follow",
                u_max, 100 * spec.mechanism_limit, model_size_));
          }
        }
        // Never "converged" with a NaN or an infinity anywhere in the answer.
        if (par::any(!all_finite(trial))) not_finite(trial, iterations, residual);
        if (extrapolate_) remember_increment(c, trial);
        return true;
      }
      if (iterations >= spec.max_iterations) return false;
      const bool new_elements =
          !factorized_ || (iterations == 0 && matrix_changes_with_temperature_) ||
          (tangent_changed_ && (options_.matrix_per_iteration() ||
                                (options_.matrix_per_step() && iterations <= 1)));
      const bool refactor = new_elements || contact_.matrix_stale(trial);
      if (refactor) assemble_and_factorize(trial, new_elements);
      // An iterative solve need only reduce this iterate's residual to 0.1 % of the step's
      // tolerance, not to its own default (an inexact Newton method with a fixed forcing term,
      // after Eisenstat and Walker): the error it leaves is a thousandth of what convergence
      // allows, and the residual recomputed from the points still decides.
      if (residual > 0) system_.set_relative_tolerance(1e-3 * spec.tolerance / residual);
      auto t0 = Clock::now();
      system_.solve(rhs, delta_);
      if (!options_checked_) {
        // PETSc ignores options it does not know: say so once it has read them (at set-up).
        options_checked_ = true;
        for (const auto& name : system_.unused_options())
          log_.warn(fmt::format("PETSc option '{}' was not used (misspelt, or for a solver that "
                                "is not in use)",
                                name));
      }
      timings_.solve += seconds_since(t0);
      if (spec.anderson) {
        // A new matrix is a new fixed-point map, and a step that doubled the residual left the
        // region where the history describes it: start the history again from here.
        if (refactor || residual > 2 * previous_residual) anderson_.reset();
        previous_residual = residual;
        free_u_.resize(dofs.n_free);
        for (int i = 0; i < dofs.n_dofs(); ++i)
          if (int k = dofs.eq[i]; k >= 0) free_u_[k] = trial.u[i];
        anderson_.accelerate(free_u_, delta_);
      }
      for (int i = 0; i < dofs.n_dofs(); ++i)
        if (int k = dofs.eq[i]; k >= 0) trial.u[i] += delta_[k];
    }
  }

  int plastic_points() const { return plastic_points_; }

  /// newton's predictor (solver.predictor: extrapolate). The step starts from the converged
  /// state (`trial`, already evaluated: `r2` is its squared residual norm). When the last step
  /// moved the free nodes by Δu_n and the new step's out-of-balance force does positive work on
  /// Δu_n (the load keeps its direction: not a reversal), the start moves on to
  /// u(t) + (Δt/Δt_n)·Δu_n, the linear extrapolation of the path (Abaqus/Standard starts its
  /// increments the same way by default). Its residual is not always smaller than that of u(t):
  /// where the plastic zone grows, the points it reaches carry their overshoot of the yield
  /// stress as out-of-balance force, but the zone and the tangents of the first iterate are
  /// close to the converged ones, which is what saves iterations (measured on the bench
  /// cylinder: 4 iterations per plastic step instead of 5-6, even where the residual norm of the
  /// extrapolated start was the larger). Returns the squared residual of the start kept; rhs_
  /// and the points hold it.
  double extrapolated_start(const State& c, State& trial, double r2) {
    const auto& dofs = m_.dofs();
    const double dt = trial.time - c.time;
    if (!extrapolate_ || last_dt_ <= 0 || dt <= 0) return r2;
    double work = 0;
    for (int k = 0; k < dofs.n_free; ++k) work += rhs_[k] * last_du_[k];
    if (only_) par::broadcast(std::span<double>(&work, 1));  // one decision for all ranks
    if (!(work > 0)) {
      log_.detail(
          "  predictor: the load reverses (no work on the last increment); no extrapolation");
      return r2;
    }
    const double scale = dt / last_dt_;
    for (int i = 0; i < dofs.n_dofs(); ++i)
      if (int k = dofs.eq[i]; k >= 0) trial.u[i] += scale * last_du_[k];
    begin_plastic_step(c, trial);  // the extrapolated start is the step's iteration 0
    const bool plain_changed = tangent_changed_;
    update_points(c, trial);
    tangent_changed_ = tangent_changed_ || plain_changed;
    const double r2x = residual_vector(trial);
    log_.detail(
        "  predictor: extrapolated start ({:.3g} of the last increment), residual {:.3e} "
        "(from the converged state {:.3e})",
        scale, std::sqrt(r2x), std::sqrt(r2));
    return r2x;
  }

  /// Keeps the free part of a converged step's displacement increment for the next predictor.
  void remember_increment(const State& c, const State& trial) {
    const auto& dofs = m_.dofs();
    last_du_.assign(dofs.n_free, 0.0);
    for (int i = 0; i < dofs.n_dofs(); ++i)
      if (int k = dofs.eq[i]; k >= 0) last_du_[k] = trial.u[i] - c.u[i];
    last_dt_ = trial.time - c.time;
  }

  double equilibrium_defect(const State& s) const {
    double r = 0;
    for (int i = 0; i < m_.dofs().n_dofs(); ++i)
      if (m_.dofs().eq[i] >= 0) {
        const double d = s.f_ext[i] + s.f_contact[i] - s.f_int[i];
        r += d * d;
      }
    return std::sqrt(r);
  }

  /// rhs_ = target + F_contact − F_int on the free dofs for the evaluated iterate (the
  /// support's forces computed here, into trial.f_contact); returns its squared norm, and in
  /// *loads2 (when given) that of target − F_int, the residual without the supports.
  double residual_vector(State& trial, double* loads2 = nullptr) {
    const auto& dofs = m_.dofs();
    if (contact_.active()) {
      const auto t0 = Clock::now();
      contact_.forces(trial);
      timings_.contact += seconds_since(t0);
    }
    double r2 = 0, l2 = 0;
    for (int i = 0; i < dofs.n_dofs(); ++i)
      if (int k = dofs.eq[i]; k >= 0) {
        const double loads = target_[i] - trial.f_int[i];
        rhs_[k] = loads + trial.f_contact[i];
        r2 += rhs_[k] * rhs_[k];
        l2 += loads * loads;
      }
    if (loads2) *loads2 = l2;
    return r2;
  }

  std::string contact_diagnosis() const { return contact_.diagnosis(); }

  /// The contact line of a converged step's log entry (empty without contact).
  std::string contact_summary(const State& s) const {
    return contact_.active() ? contact_.summary(s) : std::string();
  }

 private:
  void point_temperatures(State& s) {
    const auto& mesh = m_.mesh();
    s.temperature.resize(m_.n_points());
    s.constants.resize(m_.n_points());
    const int n_mat = static_cast<int>(m_.materials().size());
    std::vector<double> t_min(n_mat, INFINITY), t_max(n_mat, -INFINITY);
    int bad_cell = -1;  // the first cell with a temperature whose thermal strain overflows
    double bad_T = 0;
    for (int e = 0; e < mesh.cells.size(); ++e) {
      if (!m_.holds_points(e)) continue;
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
        if (bad_cell < 0 && !m_.thermal_in_range(mi, s.constants[p], T)) bad_cell = e, bad_T = T;
        t_min[mi] = std::min(t_min[mi], T);
        t_max[mi] = std::max(t_max[mi], T);
      }
    }
    // An input error, before the step is solved; every rank reports the model's first such cell.
    if (const int first = par::min(bad_cell < 0 ? INT_MAX : bad_cell); first != INT_MAX) {
      double T = first == bad_cell ? bad_T : -INFINITY;
      par::max_in_place(std::span<double>(&T, 1));
      m_.thermal_out_of_range(first, T, s.time);
    }
    par::min_in_place(std::span<double>(t_min));
    par::max_in_place(std::span<double>(t_max));
    for (int k = 0; k < n_mat; ++k)
      if (t_min[k] <= t_max[k]) m_.materials()[k].warn_outside(t_min[k], t_max[k], log_);
  }

  /// Every value of the iterate is a finite number: the forces, the displacement and this
  /// rank's points' state.
  bool all_finite(const State& s) const {
    const auto finite = [](const auto& v) {
      return std::all_of(v.begin(), v.end(), [](const auto& x) {
        if constexpr (std::is_arithmetic_v<std::decay_t<decltype(x)>>)
          return std::isfinite(x);
        else
          return x.allFinite();
      });
    };
    return finite(s.f_ext) && finite(s.u) && finite(s.stress) && finite(s.temperature) &&
           finite(s.plastic_strain) && finite(s.eps_p_eq) && finite(s.eps_ep) && finite(s.f_int) &&
           finite(s.f_contact);
  }

  /// Stops the step (SolveError, so a failed step) where a NaN or an infinity first appears in
  /// the iterate, in the order the values are computed: the external forces, the displacement,
  /// a point's state, the internal and the contact forces. Collective (the same decisions and
  /// message on every rank).
  [[noreturn]] void not_finite(const State& s, int iteration, double residual) {
    const auto& mesh = m_.mesh();
    const auto first_dof = [](const std::vector<double>& v) {
      for (std::size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i])) return static_cast<long long>(i);
      return LLONG_MAX;
    };
    const std::string when = fmt::format("in iteration {} of the step", iteration);
    const char* why =
        "the solution left the range of floating point (a load, a prescribed displacement or a "
        "temperature far too large for the material, or an iteration that diverged)";
    const auto at_node = [&](const char* what, const std::vector<double>& v) {
      const long long i = par::min(first_dof(v));
      if (i == LLONG_MAX) return;
      throw SolveError(fmt::format("a NaN or an infinity appeared in the {} at node {} ({}) {}: {}",
                                   what, mesh.node_tag[i / 3], "xyz"[i % 3], when, why));
    };
    at_node("external forces", s.f_ext);
    at_node("displacement", s.u);
    // Points: the first cell, and whether its stress (code 0) or its plastic state (1) is bad.
    long long cell_code = LLONG_MAX;
    for (int e = 0; e < mesh.cells.size() && cell_code == LLONG_MAX; ++e)
      for (int p = m_.point_offset(e); p < m_.point_offset(e + 1); ++p) {
        const bool stress = !s.stress[p].allFinite() || !std::isfinite(s.temperature[p]);
        if (stress || !s.plastic_strain[p].allFinite() || !std::isfinite(s.eps_p_eq[p]) ||
            !std::isfinite(s.eps_ep[p])) {
          cell_code = 2LL * e + (stress ? 0 : 1);
          break;
        }
      }
    if (const long long cc = par::min(cell_code); cc != LLONG_MAX) {
      const int e = static_cast<int>(cc / 2);
      throw SolveError(fmt::format(
          "a NaN or an infinity appeared in the {} at element {} (material '{}') {}: {}",
          cc % 2 == 0 ? "stress" : "plastic strain", mesh.cells.tag[e],
          m_.material_of(e).spec->name, when, why));
    }
    at_node("internal forces", s.f_int);
    at_node("contact forces", s.f_contact);
    // Every value is finite, but the forces are too large to measure: the squares in the
    // residual's norms overflow. Name the largest force (root's figures are the ones printed).
    const char* what = "residual";
    double largest = 0;
    std::size_t at = 0;
    for (const auto& [name, v] :
         {std::pair{"external force", &s.f_ext}, std::pair{"internal force", &s.f_int},
          std::pair{"contact force", &s.f_contact}})
      for (std::size_t i = 0; i < v->size(); ++i)
        if (std::abs((*v)[i]) > largest) largest = std::abs((*v)[i]), at = i, what = name;
    throw SolveError(fmt::format(
        "the relative residual is {} {}: the {} at node {} is {:g}, too large to measure "
        "(its square overflows): {}",
        residual, when, what, mesh.node_tag[at / 3], largest, why));
  }

  /// Per point, what stays fixed during the step (flow direction, start slope, the curve at
  /// t+Δt) and the scheme's initial parameters.
  void begin_plastic_step(const State& c, const State& trial) {
    const auto& mesh = m_.mesh();
    const int n_cells = mesh.cells.size();
#pragma omp parallel for schedule(static) if (n_cells > 4000)
    for (int e = 0; e < n_cells; ++e) {
      const auto& mat = m_.material_of(e);
      if (!mat.plastic() || !mine(e)) continue;
      for (int p = m_.point_offset(e); p < m_.point_offset(e + 1); ++p)
        point_step_[p] = begin_point_step(options_, trial.constants[p], *mat.hardening,
                                          trial.temperature[p], mat.elastic_unloading, c.stress[p],
                                          c.eps_p_eq[p], c.flowing[p] != 0, point_iter_[p]);
    }
  }

  /// Point update and internal forces. Elastic materials: σ = σ(t) + D(t+Δt)(Δε − Δε^th),
  /// (1.9), (1.12). Plastic ones: the scheme's point law (solve/schemes.hpp).
  void update_points(const State& c, State& trial) {
    auto t0 = Clock::now();
    const auto& mesh = m_.mesh();
    trial.f_int.assign(m_.dofs().n_dofs(), 0.0);
    std::atomic<bool> changed{false};
    std::atomic<int> undefined_cell{-1}, negative_secant_cell{-1};
    m_.assembler().vector(
        [&](int e, CellBuffers& b) {
          const auto nodes = mesh.cells.nodes(e);
          const int n = static_cast<int>(nodes.size());
          const bool plastic = m_.material_of(e).plastic();
          Vec3 x[max_cell_nodes];
          double du[3 * max_cell_nodes];
          for (int a = 0; a < n; ++a) {
            x[a] = mesh.x[nodes[a]];
            for (int d = 0; d < 3; ++d)
              du[3 * a + d] = trial.u[3 * nodes[a] + d] - c.u[3 * nodes[a] + d];
          }
          CellKinematics& kin = kinematics();
          kin.compute(reference_table(mesh.cells.type[e]), std::span<const Vec3>(x, n));
          for (int q = 0; q < kin.points; ++q) {
            const int p = m_.point_offset(e) + q;
            const Voigt d_eps = kin.strain(q, du);
            if (!plastic) {
              trial.stress[p] =
                  elastic_stress_update(c.constants[p], c.temperature[p], trial.constants[p],
                                        trial.temperature[p], c.stress[p], d_eps);
            } else {
              const Voigt d_mech = d_eps - thermal_strain_increment(
                                               c.constants[p], c.temperature[p], trial.constants[p],
                                               trial.temperature[p], c.stress[p]);
              const PointUpdate u = evaluate_point(options_, trial.constants[p], point_step_[p],
                                                   point_iter_[p], c.stress[p], d_mech);
              if (u.undefined) {
                int none = -1;
                undefined_cell.compare_exchange_strong(none, e);
                trial.stress[p] = c.stress[p];
                continue;
              }
              if (u.negative_secant) {
                int none = -1;
                negative_secant_cell.compare_exchange_strong(none, e);
              }
              trial.stress[p] = u.sigma;
              trial.plastic_strain[p] = c.plastic_strain[p] + u.d_lambda * u.z;
              trial.eps_p_eq[p] = std::max(0.0, c.eps_p_eq[p] + u.d_lambda);
              trial.eps_ep[p] = u.eps_ep;
              trial.eps_ep_max[p] = std::max(c.eps_ep_max[p], u.eps_ep);
              trial.flowing[p] = u.plastic;
              defect_sigma_[p] = u.defect_sigma;
              defect_eps_[p] = u.defect_eps;
              const Tangent& old = tangent_[p];
              if (old.dev_scale != u.tangent.dev_scale || old.coef != u.tangent.coef ||
                  old.v != u.tangent.v) {
                tangent_[p] = u.tangent;
                changed.store(true, std::memory_order_relaxed);
              }
            }
            kin.add_bt_sigma(q, trial.stress[p], kin.dv[q], b.fe);
          }
        },
        trial.f_int, only_);
    // Every rank takes the same decisions: the flags and the failing cells over all ranks.
    const int undefined = par::max(undefined_cell.load());
    negative_secant_cell_ = par::max(negative_secant_cell.load());
    tangent_changed_ = par::any(changed.load());
    if (only_) par::sum_in_place(std::span<double>(trial.f_int));
    if (const int e = undefined; e >= 0) {
      timings_.material += seconds_since(t0);
      throw SolveError(fmt::format(
          "scheme '{}' needs the strain form ε̃ = F(σ̃) of the curve of material '{}' above the "
          "largest stress the curve reaches (element {}): F is not defined there (perfect "
          "plasticity, a table's flat end). Use initial-stress, initial-stress-stiffness, "
          "variable-stiffness with curve_form: stress, or newton",
          scheme_name(options_.kind), m_.material_of(e).spec->name, m_.mesh().cells.tag[e]));
    }
    if (plastic_) measures(trial);
    timings_.material += seconds_since(t0);
  }

  /// Δ^σ and Δ^ε of the report, made global: the volume-weighted root mean square of the
  /// points' numerators over that of σ̃ (resp. ε̃^{e+p}) over the plastic materials.
  void measures(const State& trial) {
    double ns = 0, ds = 0, ne = 0, de = 0;
    int n_plastic = 0;
    const auto& mesh = m_.mesh();
    for (int e = 0; e < mesh.cells.size(); ++e) {
      if (!m_.material_of(e).plastic() || !mine(e)) continue;
      for (int p = m_.point_offset(e); p < m_.point_offset(e + 1); ++p) {
        const double w = point_volume_[p], q = von_mises(trial.stress[p]);
        ns += w * defect_sigma_[p] * defect_sigma_[p];
        ds += w * q * q;
        ne += w * defect_eps_[p] * defect_eps_[p];
        de += w * trial.eps_ep[p] * trial.eps_ep[p];
        n_plastic += trial.flowing[p];
      }
    }
    double sums[5] = {ns, ds, ne, de, static_cast<double>(n_plastic)};
    par::sum_in_place(std::span<double>(sums));
    ns = sums[0], ds = sums[1], ne = sums[2], de = sums[3];
    n_plastic = static_cast<int>(sums[4]);
    delta_sigma_ = ds > 0 ? std::sqrt(ns / ds) : 0.0;
    delta_eps_ = de > 0 ? std::sqrt(ne / de) : 0.0;
    plastic_points_ = n_plastic;
  }

  /// Assembles the matrix (the elements' part only when `new_elements` or when it was never
  /// kept: a change of the contact alone starts from the elements' part of the last assembly)
  /// and factorizes it.
  void assemble_and_factorize(const State& trial, bool new_elements) {
    auto t0 = Clock::now();
    if (new_elements || !contact_.active() || !system_.restore_cells()) {
      system_.assemble_cells([&](int e, CellBuffers& b) { element_matrix(trial, e, b); });
      if (contact_.active()) system_.keep_cells();
    }
    if (contact_.active())
      contact_.add_matrix(trial, [&](int a, int b, const Mat3& block) { system_.add_block(a, b, block); });
    timings_.assembly += seconds_since(t0);
    factorize();
  }

  /// The matrix of cell e for the iterate's tangents into b.ke (zeroed by the caller): B̄ᵀCB̄
  /// over the cell's points, C the point's tangent (elastic D, or the scheme's matrix).
  void element_matrix(const State& trial, int e, CellBuffers& b) const {
    const auto& mesh = m_.mesh();

    const auto nodes = mesh.cells.nodes(e);
    const int n = static_cast<int>(nodes.size());
    const int nd = 3 * n;
    const bool plastic = m_.material_of(e).plastic();
    const Tangent elastic;
    Vec3 x[max_cell_nodes], bv[max_cell_nodes];
    for (int a = 0; a < n; ++a) x[a] = mesh.x[nodes[a]];
    CellKinematics& kin = kinematics();
    kin.compute(reference_table(mesh.cells.type[e]), std::span<const Vec3>(x, n));
    for (int q = 0; q < kin.points; ++q) {
      const double w = kin.dv[q];
      const double* dNdx = kin.grad(q);
      const int p = m_.point_offset(e) + q;
      const ElasticConstants& k = trial.constants[p];
      // C = D + dev_scale·2G·I_dev + coef·v vᵀ (material/plastic_point.hpp): an isotropic
      // part and, for plastic points, a rank-one part.
      const Tangent& t = plastic ? tangent_[p] : elastic;
      const double lam = t.lambda(k) * w, mu = t.mu(k) * w;
      if (t.coef != 0) {
        // B_aᵀv per node; K_ab += coef·(B_aᵀv)(B_bᵀv)ᵀ.
        const Voigt& v = t.v;
        for (int a = 0; a < n; ++a) {
          const double* g = dNdx + 3 * a;
          bv[a] = Vec3(g[0] * v[0] + g[2] * v[4] + g[1] * v[5],
                       g[1] * v[1] + g[2] * v[3] + g[0] * v[5],
                       g[2] * v[2] + g[1] * v[3] + g[0] * v[4]);
        }
        const double cw = t.coef * w;
        for (int a = 0; a < n; ++a)
          for (int bb = a; bb < n; ++bb)
            for (int i = 0; i < 3; ++i)
              for (int j = 0; j < 3; ++j)
                b.ke[(3 * a + i) * nd + 3 * bb + j] += cw * bv[a][i] * bv[bb][j];
      }
      if (kin.bbar) {
        // B̄_a = B_a + (1/3) m d_aᵀ: K_ab gains (1/3)(B_aᵀCm) d_bᵀ + (1/3) d_a (B_bᵀCm)ᵀ
        // + (1/9)(mᵀCm) d_a d_bᵀ, with Cm = C·(1, 1, 1, 0, 0, 0).
        Voigt m_vec;
        m_vec << 1, 1, 1, 0, 0, 0;
        const Voigt cm = t.times(k, m_vec) * w;
        const double mcm = (cm[0] + cm[1] + cm[2]) / 9;
        const double* dq = kin.corr(q);
        for (int a = 0; a < n; ++a) {
          const double* g = dNdx + 3 * a;
          bv[a] = Vec3(g[0] * cm[0] + g[2] * cm[4] + g[1] * cm[5],
                       g[1] * cm[1] + g[2] * cm[3] + g[0] * cm[5],
                       g[2] * cm[2] + g[1] * cm[3] + g[0] * cm[4]) /
                  3;
        }
        for (int a = 0; a < n; ++a)
          for (int bb = a; bb < n; ++bb)
            for (int i = 0; i < 3; ++i)
              for (int j = 0; j < 3; ++j)
                b.ke[(3 * a + i) * nd + 3 * bb + j] += bv[a][i] * dq[3 * bb + j] +
                                                       dq[3 * a + i] * bv[bb][j] +
                                                       mcm * dq[3 * a + i] * dq[3 * bb + j];
      }
      // K_ab = B_aᵀ D B_b for isotropic D: λ g_a g_bᵀ + μ (g_b g_aᵀ + (g_a·g_b) I).
      for (int a = 0; a < n; ++a) {
        const Vec3 ga(dNdx[3 * a], dNdx[3 * a + 1], dNdx[3 * a + 2]);
        for (int bb = a; bb < n; ++bb) {
          const Vec3 gb(dNdx[3 * bb], dNdx[3 * bb + 1], dNdx[3 * bb + 2]);
          const double dot = mu * ga.dot(gb);
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
              const double v =
                  lam * ga[i] * gb[j] + mu * gb[i] * ga[j] + (i == j ? dot : 0.0);
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
  }

  /// This rank works on cell e (every cell without the PETSc back end on several ranks).
  bool mine(int e) const { return !only_ || (*only_)[e]; }

  /// Factorizes the assembled matrix.
  void factorize() {
    const auto t0 = Clock::now();
    try {
      system_.factorize();
    } catch (const LinearSystemError& e) {
      if (negative_secant_cell_ < 0) throw;
      // variable-stiffness with a negative secant: say why the matrix is indefinite (a plain
      // SolveError: the step failed, the supports are not to blame).
      throw SolveError(fmt::format(
          "{}: scheme 'variable-stiffness' has a negative secant slope of the curve of material "
          "'{}' at element {} (the stress at the start of the step lies above the curve along "
          "the step's flow direction, as a strong turn of the stress under an indenter leaves "
          "it); use newton or initial-stress",
          e.what(), m_.material_of(negative_secant_cell_).spec->name,
          m_.mesh().cells.tag[negative_secant_cell_]));
    }
    ++factorizations_;
    factorized_ = true;
    timings_.factorization += seconds_since(t0);
  }

  /// Per-thread scratch for a cell's kinematics (about 26 kB: not on every stack frame).
  static CellKinematics& kinematics() {
    thread_local CellKinematics kin;
    return kin;
  }

  const Model& m_;
  LinearSystem& system_;
  bool options_checked_ = false;             ///< unused options of the back end were reported
  const std::vector<char>* only_ = nullptr;  ///< this rank's cells, on more than one rank
  Log& log_;
  Timings& timings_;
  bool matrix_changes_with_temperature_ = false;
  bool factorized_ = false;
  std::vector<double> target_, rhs_, delta_;
  // Plasticity
  bool plastic_ = false;
  SchemeOptions options_;
  std::vector<PointStep> point_step_;
  std::vector<PointIteration> point_iter_;
  std::vector<Tangent> tangent_;  ///< per point: the matrix of the last assembly
  std::vector<double> defect_sigma_, defect_eps_, point_volume_;
  bool tangent_changed_ = false;
  double delta_sigma_ = 0, delta_eps_ = 0;
  int plastic_points_ = 0;
  int factorizations_ = 0;
  int negative_secant_cell_ = -1;  ///< a cell whose variable-stiffness secant is negative
  double model_size_ = 0;  ///< diagonal of the mesh's bounding box
  // newton's predictor (solver.predictor): the last converged increment of the free unknowns
  // and its Δt
  bool extrapolate_ = false;
  std::vector<double> last_du_;
  double last_dt_ = 0;
  // solver.acceleration: anderson
  Anderson anderson_{5};
  ContactStep contact_;
  std::vector<double> free_u_;
};

}  // namespace

AnalysisResult run_analysis(const Model& model, LinearSystem& solver, Log& log, Timings& timings,
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
  // The step times are taken one at a time (a case may have a million steps): the deque holds
  // the current one and the cut-back targets before it.
  std::deque<Target> targets;
  std::size_t next_step = 0;
  const auto take_next_step = [&] {
    if (targets.empty() && next_step < spec.times.size())
      targets.push_back({spec.times[next_step++], 0});
  };
  take_next_step();
  int factorizations_before = 0;
  while (!targets.empty()) {
    const double t1 = targets.front().time;
    const int depth = targets.front().depth;
    int iterations = 0;
    double residual = 0;
    bool ok = false;
    std::string why;
    try {
      ok = stepper.step(committed, t1, trial, iterations, residual);
      if (!ok) {
        why = fmt::format("no convergence in {} iterations (relative residual {:.3e})", iterations,
                          residual);
        if (const std::string c = stepper.contact_diagnosis(); !c.empty()) why += "; " + c;
      }
    } catch (const SolverOptionsError& e) {
      throw InputError(SourceLocation{model.spec().file.string(), 0, 0, "solver.petsc_options"},
                       std::string(e.what()) +
                           ": PETSc cannot set the solver up with the options given "
                           "(solver.petsc_options, --petsc or PETSC_OPTIONS)");
    } catch (const LinearSystemError& e) {
      // The first solve of the analysis: the matrix of the elastic body itself cannot be
      // solved, the supports do not hold it.
      if (result.steps == 0 && iterations == 0)
        throw InputError(SourceLocation{model.spec().file.string(), 0, 0, "boundary"},
                         std::string(e.what()) +
                             ": the body is not held against rigid-body motion (translations "
                             "and rotations); check the displacement conditions");
      why = e.what();
    } catch (const SolveError& e) {
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
      result.factorizations = stepper.factorizations();
      result.failure =
          fmt::format("step to t = {:g} did not converge after {} cut-backs: {}", t1, depth, why);
      log.info("{}", result.failure);
      return result;
    }
    targets.pop_front();
    take_next_step();
    std::swap(committed, trial);
    ++result.steps;
    StepReport report;
    report.step = result.steps;
    report.time = t1;
    report.iterations = iterations;
    report.residual = residual;
    report.delta_sigma = stepper.delta_sigma();
    report.delta_eps = stepper.delta_eps();
    report.factorizations = stepper.factorizations() - factorizations_before;
    report.plastic_points = stepper.plastic_points();
    report.last = targets.empty();
    report.write_fields = report.last || report.step % model.spec().output.every == 0;
    factorizations_before = stepper.factorizations();
    result.factorizations = stepper.factorizations();
    if (model.has_plasticity()) {
      log.info("step {:4d}  t = {:<10.6g} iterations {:3d}  residual {:.2e}  plastic points {}",
               report.step, report.time, report.iterations, report.residual, report.plastic_points);
      stepper.check_curves(committed);
    } else {
      log.info("step {:4d}  t = {:<10.6g} iterations {:3d}  residual {:.2e}", report.step,
               report.time, report.iterations, report.residual);
    }
    if (const std::string line = stepper.contact_summary(committed); !line.empty())
      log.info("           {}", line);
    const auto t0 = Clock::now();
    observer.step_done(report, committed,
                       recover_fields(model, committed, report.write_fields));
    timings.output += seconds_since(t0);
  }
  return result;
}

}  // namespace hencky
