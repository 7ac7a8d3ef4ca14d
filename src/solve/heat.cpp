#include "solve/heat.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>

#include "core/interrupt.hpp"
#include "fem/geometry.hpp"
#include "fem/quadrature.hpp"
#include "fem/reference_element.hpp"
#include "linalg/gmres.hpp"
#include "parallel/mpi.hpp"
#include "parallel/nodal_layout.hpp"

namespace hencky {

namespace {

/// The quadrature of the heat terms: at least the mechanical one, and exact for the capacity
/// (mass) matrix of an affine cell.
int heat_degree(CellType type) {
  const int order = cell_linear(type) == type ? 1 : 2;
  return std::max(default_degree(type), 2 * order);
}

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

// ---------------------------------------------------------------------------------------------
// HeatCapacity

HeatCapacity::HeatCapacity(const PropertyTable& density, const PropertyTable& specific_heat,
                           double T_ref)
    : rho_(&density), c_(&specific_heat) {
  T_ = density.temperature;
  T_.insert(T_.end(), specific_heat.temperature.begin(), specific_heat.temperature.end());
  T_.push_back(T_ref);
  std::sort(T_.begin(), T_.end());
  T_.erase(std::unique(T_.begin(), T_.end()), T_.end());
  H_.assign(T_.size(), 0.0);
  const std::size_t i0 = std::lower_bound(T_.begin(), T_.end(), T_ref) - T_.begin();
  for (std::size_t i = i0 + 1; i < T_.size(); ++i) H_[i] = H_[i - 1] + integral(T_[i - 1], T_[i]);
  for (std::size_t i = i0; i-- > 0;) H_[i] = H_[i + 1] - integral(T_[i], T_[i + 1]);
}

double HeatCapacity::integral(double a, double b) const {
  const double m = 0.5 * (a + b), h = 0.5 * (b - a), g = h / std::sqrt(3.0);
  return h * (rho_c(m - g) + rho_c(m + g));
}

double HeatCapacity::enthalpy(double T) const {
  // The piece that holds T; beyond the ends ρc is constant and the end piece extends.
  const auto it = std::upper_bound(T_.begin(), T_.end(), T);
  const std::size_t i = it == T_.begin() ? 0 : static_cast<std::size_t>(it - T_.begin()) - 1;
  return H_[i] + integral(T_[i], T);
}

// ---------------------------------------------------------------------------------------------
// HeatSolver

/// The case's expressions, one copy per thread (Expression is not thread-safe).
struct HeatSolver::PointExpressions {
  Expression source;
  std::vector<Expression> value, ambient;  ///< per heat.boundary entry
};

/// What a pass over the cells gives, per node (whole on every rank): R(T, t1) and the
/// capacity term C = ∫ (H(T) − H(T0)) N dV, each with its scale (the sum of the magnitudes
/// of the terms it is made of, which bounds its round-off).
struct HeatSolver::Evaluation {
  std::vector<double> R, SR, C, SC;
  std::vector<double> G, S;  ///< the step's residual and its scale
};

HeatSolver::HeatSolver(const Model& model, const SystemFactory& make_system, Log& log)
    : model_(model), spec_(model.spec().heat), log_(log) {
  system_ = make_system(model.heat_assembler(), model.heat_dofs());
  const double T_ref = model.reference_temperature();
  for (const MaterialModel& m : model.materials())
    capacity_.push_back(spec_.transient
                            ? HeatCapacity(m.spec->density, m.spec->specific_heat, T_ref)
                            : HeatCapacity());
  PointExpressions ex{spec_.source, {}, {}};
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
  R_last_.assign(model.mesh().n_nodes(), 0.0);
  S_last_.assign(model.mesh().n_nodes(), 0.0);
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
  const auto t_start = std::chrono::steady_clock::now();
  if (spec_.transient) {
    Evaluation ev;
    evaluate(s0.T, s0, 0.0, false, ev);
    R_last_ = std::move(ev.R);
    S_last_ = std::move(ev.SR);
    natural_flows(s0.T, 0.0, s0.flow_now);
    snapshots_.push_back(std::move(s0));
  } else {
    HeatSnapshot steady;
    std::string why;
    if (!solve(s0, 0.0, steady, why))
      throw HeatDivergence("heat: the steady temperature at t = 0 did not converge: " + why);
    snapshots_.push_back(std::move(steady));
  }
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
}

void HeatSolver::fixed_temperatures(double t, std::vector<double>& T) const {
  const auto& fixed = model_.heat_fixed();
  for (std::size_t n = 0; n < fixed.size(); ++n)
    if (fixed[n] >= 0) {
      const Vec3& x = model_.mesh().x[n];
      T[n] = spec_.boundary[fixed[n]].value.eval_checked(x.x(), x.y(), x.z(), t, "temperature");
    }
}

namespace {

/// The heat flux into the body of a natural condition at a face point, its derivative with
/// respect to T and the magnitude of its terms. Throws InputError for a negative h or an
/// emissivity outside 0 .. 1.
struct FaceFlux {
  double q = 0, dq_dT = 0, scale = 0;
};
FaceFlux face_flux(const HeatBoundarySpec& bc, const Expression& value, const Expression& ambient,
                   const HeatSpec& spec, const Vec3& p, double t, double T) {
  FaceFlux f;
  const char* what = to_string(bc.kind);
  const double v = value.eval_checked(p.x(), p.y(), p.z(), t, what);
  switch (bc.kind) {
    case HeatBoundarySpec::Kind::flux:
      f.q = v;
      f.scale = std::abs(v);
      break;
    case HeatBoundarySpec::Kind::convection: {
      if (v < 0)
        throw InputError(bc.value_where,
                         fmt::format("\"{}\" gives the film coefficient h = {:g} at ({:g}, {:g}, "
                                     "{:g}), t = {:g}; h must be >= 0",
                                     value.text(), v, p.x(), p.y(), p.z(), t));
      const double Ta = ambient.eval_checked(p.x(), p.y(), p.z(), t, "ambient");
      f.q = v * (Ta - T);
      f.dq_dT = -v;
      f.scale = v * (std::abs(Ta) + std::abs(T));
      break;
    }
    case HeatBoundarySpec::Kind::radiation: {
      if (v < 0 || v > 1)
        throw InputError(bc.value_where,
                         fmt::format("\"{}\" gives the emissivity {:g} at ({:g}, {:g}, {:g}), "
                                     "t = {:g}; it must be in 0 .. 1",
                                     value.text(), v, p.x(), p.y(), p.z(), t));
      const double Ta = ambient.eval_checked(p.x(), p.y(), p.z(), t, "ambient");
      const double z = *spec.absolute_zero, es = v * spec.stefan_boltzmann;
      const double a = Ta - z, b = std::max(T - z, 0.0);
      f.q = es * (a * a * a * a - b * b * b * b);
      f.dq_dT = -4 * es * b * b * b;
      f.scale = es * (a * a * a * a + b * b * b * b);
      break;
    }
    case HeatBoundarySpec::Kind::temperature:
      break;
  }
  return f;
}

/// Calls f(N, nf, da, p) at each quadrature point of heat face hf: its shape functions, node
/// count, area element and position.
template <class F>
void for_face_points(const Mesh& mesh, const HeatFace& hf, F&& f) {
  const auto fnodes = mesh.faces.nodes(hf.face);
  const int nf = static_cast<int>(fnodes.size());
  const CellType ft = mesh.faces.type[hf.face];
  const ReferenceTable& ftab = reference_table(ft, heat_degree(ft));
  Vec3 xf[max_cell_nodes];
  for (int a = 0; a < nf; ++a) xf[a] = mesh.x[fnodes[a]];
  const std::span<const Vec3> xfs(xf, nf);
  for (int q = 0; q < ftab.n_points; ++q)
    f(&ftab.N[static_cast<std::size_t>(q) * nf], nf,
      face_normal(ftab, q, xfs).norm() * ftab.weights[q], point_position(ftab, q, xfs));
}

/// A volume cell as both passes over the cells read it: its nodes, quadrature table,
/// material, node positions and nodal temperatures.
struct HeatCell {
  std::span<const int> nodes;
  int n;
  const ReferenceTable& tab;
  const MaterialSpec& mat;
  Vec3 x[max_cell_nodes];
  double T[max_cell_nodes];
  HeatCell(const Model& model, int e, const std::vector<double>& T_nodal)
      : nodes(model.mesh().cells.nodes(e)),
        n(static_cast<int>(nodes.size())),
        tab(reference_table(model.mesh().cells.type[e], heat_degree(model.mesh().cells.type[e]))),
        mat(*model.material_of(e).spec) {
    for (int a = 0; a < n; ++a) {
      x[a] = model.mesh().x[nodes[a]];
      T[a] = T_nodal[nodes[a]];
    }
  }
  std::span<const Vec3> xs() const { return {x, static_cast<std::size_t>(n)}; }
};

}  // namespace

void HeatSolver::evaluate(const std::vector<double>& T, const HeatSnapshot& from, double t1,
                          bool matrix, Evaluation& ev) {
  const Mesh& mesh = model_.mesh();
  const int n_nodes = mesh.n_nodes();
  // R, SR, C, SC side by side: one reduction over the ranks.
  std::vector<double> sums(4 * static_cast<std::size_t>(n_nodes), 0.0);
  double* R = sums.data();
  double* SR = R + n_nodes;
  double* C = SR + n_nodes;
  double* SC = C + n_nodes;
  const bool transient = spec_.transient;
  const double dt = t1 - from.time;
  // The matrix of G: ∂C/∂T / Δt + θ ∂R/∂T (transient), ∂R/∂T (steady).
  const double theta = transient ? theta_ : 1.0;
  const double inv_dt = transient && dt > 0 ? 1.0 / dt : 0.0;
  const bool source = !(spec_.source.is_constant() && spec_.source(0, 0, 0, 0) == 0);
  std::exception_ptr error;
  std::mutex error_mutex;

  // Cells of one colour share no node, and the assembler runs the kernel colour by colour:
  // the kernel adds its cell's vectors into the nodal sums itself.
  auto kernel = [&](int e, CellBuffers& b) {
    try {
      const HeatCell cell(model_, e, T);
      const auto nodes = cell.nodes;
      const int n = cell.n;
      const ReferenceTable& tab = cell.tab;
      const MaterialSpec& mat = cell.mat;
      const double* Te = cell.T;
      const HeatCapacity& cap = capacity_[model_.material_index(e)];
      const PointExpressions& ex = expressions_[omp_get_thread_num()];
      double T0e[max_cell_nodes], dNdx[3 * max_cell_nodes];
      double r[max_cell_nodes] = {}, sr[max_cell_nodes] = {}, c[max_cell_nodes] = {},
             sc[max_cell_nodes] = {};
      for (int a = 0; a < n; ++a) T0e[a] = from.T[nodes[a]];
      const std::span<const Vec3> xs = cell.xs();
      double* ke = b.ke;
      for (int q = 0; q < tab.n_points; ++q) {
        const double dv = physical_gradients(tab, q, xs, dNdx) * tab.weights[q];
        const double* N = &tab.N[static_cast<std::size_t>(q) * n];
        double Tq = 0, T0q = 0;
        Vec3 g = Vec3::Zero(), g_abs = Vec3::Zero();
        for (int a = 0; a < n; ++a) {
          Tq += N[a] * Te[a];
          T0q += N[a] * T0e[a];
          const Vec3 ga(dNdx[3 * a], dNdx[3 * a + 1], dNdx[3 * a + 2]);
          g += ga * Te[a];
          g_abs += ga.cwiseAbs() * std::abs(Te[a]);
        }
        const double k = mat.conductivity(Tq);
        for (int a = 0; a < n; ++a) {
          const Vec3 ga(dNdx[3 * a], dNdx[3 * a + 1], dNdx[3 * a + 2]);
          r[a] += k * ga.dot(g) * dv;
          sr[a] += k * ga.cwiseAbs().dot(g_abs) * dv;
          if (matrix)
            for (int bb = 0; bb < n; ++bb)
              ke[a * n + bb] +=
                  theta * k *
                  (ga[0] * dNdx[3 * bb] + ga[1] * dNdx[3 * bb + 1] + ga[2] * dNdx[3 * bb + 2]) * dv;
        }
        if (source) {
          const Vec3 p = point_position(tab, q, xs);
          const double Q = ex.source(p.x(), p.y(), p.z(), t1, Tq);
          if (!std::isfinite(Q))
            throw InputError(spec_.source.where(),
                             fmt::format("source: \"{}\" gives {:g} at ({:g}, {:g}, {:g}), t = "
                                         "{:g}, T = {:g}; expected a finite value",
                                         spec_.source.text(), Q, p.x(), p.y(), p.z(), t1, Tq));
          double m = 0;  // the matrix's −∂Q/∂T, where it is >= 0
          if (matrix && spec_.source.depends_on_temperature()) {
            const double h = 1e-6 * std::max(1.0, std::abs(Tq));
            const double dQ = (ex.source(p.x(), p.y(), p.z(), t1, Tq + h) -
                               ex.source(p.x(), p.y(), p.z(), t1, Tq - h)) /
                              (2 * h);
            if (std::isfinite(dQ) && dQ < 0) m = -dQ;
          }
          for (int a = 0; a < n; ++a) {
            r[a] -= Q * N[a] * dv;
            sr[a] += std::abs(Q) * N[a] * dv;
            if (m > 0)
              for (int bb = 0; bb < n; ++bb) ke[a * n + bb] += theta * m * N[a] * N[bb] * dv;
          }
        }
        if (transient) {
          const double H = cap.enthalpy(Tq), H0 = cap.enthalpy(T0q);
          const double m = cap.rho_c(Tq) * inv_dt;
          for (int a = 0; a < n; ++a) {
            c[a] += (H - H0) * N[a] * dv;
            sc[a] += (std::abs(H) + std::abs(H0)) * N[a] * dv;
            if (matrix && m > 0)
              for (int bb = 0; bb < n; ++bb) ke[a * n + bb] += m * N[a] * N[bb] * dv;
          }
        }
      }
      // The cell's faces with a flux, convection or radiation condition.
      const auto& faces = model_.heat_faces();
      for (int i = model_.heat_face_start(e); i < model_.heat_face_start(e + 1); ++i) {
        const HeatFace& hf = faces[i];
        const HeatBoundarySpec& bc = spec_.boundary[hf.boundary];
        for_face_points(mesh, hf, [&](const double* N, int nf, double da, const Vec3& p) {
          double Tq = 0;
          for (int a = 0; a < nf; ++a) Tq += N[a] * Te[hf.local[a]];
          const FaceFlux f =
              face_flux(bc, ex.value[hf.boundary], ex.ambient[hf.boundary], spec_, p, t1, Tq);
          for (int a = 0; a < nf; ++a) {
            const int la = hf.local[a];
            r[la] -= f.q * N[a] * da;
            sr[la] += f.scale * N[a] * da;
            if (matrix && f.dq_dT < 0)
              for (int bb = 0; bb < nf; ++bb)
                ke[la * n + hf.local[bb]] -= theta * f.dq_dT * N[a] * N[bb] * da;
          }
        });
      }
      for (int a = 0; a < n; ++a) {
        const int node = nodes[a];
        R[node] += r[a];
        SR[node] += sr[a];
        C[node] += c[a];
        SC[node] += sc[a];
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
    }
  };
  if (matrix)
    system_->assemble_cells(kernel);
  else
    model_.heat_assembler().matrices(
        kernel, [](int, const double*) {}, system_->own_cells());
  // Every rank stops on an error one of them found: the one that found it says what.
  par::rethrow_anywhere(error, SourceLocation{model_.spec().file.string(), 0, 0, "heat"},
                        "the heat analysis met an input error on another MPI rank");
  model_.layout().sum_blocks(sums, 4);
  ev.R.assign(R, R + n_nodes);
  ev.SR.assign(SR, SR + n_nodes);
  ev.C.assign(C, C + n_nodes);
  ev.SC.assign(SC, SC + n_nodes);
  ev.G.resize(n_nodes);
  ev.S.resize(n_nodes);
  for (int i = 0; i < n_nodes; ++i) {
    if (transient) {
      ev.G[i] = ev.C[i] * inv_dt + theta * ev.R[i] + (1 - theta) * R_last_[i];
      ev.S[i] = ev.SC[i] * inv_dt + theta * ev.SR[i] + (1 - theta) * S_last_[i];
    } else {
      ev.G[i] = ev.R[i];
      ev.S[i] = ev.SR[i];
    }
  }
}

void HeatSolver::natural_flows(const std::vector<double>& T, double t,
                               std::vector<double>& q) const {
  const Mesh& mesh = model_.mesh();
  const PointExpressions& ex = expressions_[0];
  q.assign(spec_.boundary.size(), 0.0);
  for (const HeatFace& hf : model_.heat_faces()) {
    const auto fnodes = mesh.faces.nodes(hf.face);
    for_face_points(mesh, hf, [&](const double* N, int nf, double da, const Vec3& p) {
      double Tq = 0;
      for (int a = 0; a < nf; ++a) Tq += N[a] * T[fnodes[a]];
      q[hf.boundary] += face_flux(spec_.boundary[hf.boundary], ex.value[hf.boundary],
                                  ex.ambient[hf.boundary], spec_, p, t, Tq)
                            .q *
                        da;
    });
  }
  model_.layout().total(q);  // a distributed mesh's outer faces are each on one part
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
  double r_first = 0, last_correction = INFINITY, t_scale = 1.0;
  for (int it = 0;; ++it) {
    // A linear problem keeps its factor while Δt and θ do.
    const double key = transient ? dt * (2 - theta_) : 0.0;  // one number for (Δt, θ ∈ [½, 1])
    const bool matrix = !linear_ || factored_dt_ != key;
    evaluate(to.T, from, t1, matrix && n_free > 0, ev);
    const double g = norm(model_.layout(), ev.G, eq), s = norm(model_.layout(), ev.S, eq);
    const double r = s > 0 ? g / s : 0.0;
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
      iterations_ += it;
      last_iterations_ = it;
      last_residual_ = r;
      natural_flows(to.T, t1, to.flow_now);
      const double theta = transient ? theta_ : 1.0;
      const std::vector<double>& q0 = snapshots_.empty() ? to.flow_now : from.flow_now;
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
      R_last_ = std::move(ev.R);
      S_last_ = std::move(ev.SR);
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

void HeatSolver::jacobian_times(const std::vector<double>& T, const HeatSnapshot& from, double t1,
                                const std::vector<double>& v, std::vector<double>& out) {
  const Mesh& mesh = model_.mesh();
  out.assign(mesh.n_nodes(), 0.0);
  const bool transient = spec_.transient;
  const double theta = transient ? theta_ : 1.0;
  const double dt = t1 - from.time, inv_dt = transient && dt > 0 ? 1.0 / dt : 0.0;
  const bool source_of_T = spec_.source.depends_on_temperature();
  // As evaluate(): colour by colour, each cell adds into the nodes' sums itself. The values
  // met here were all evaluated (and checked) by evaluate() at the same T.
  auto kernel = [&](int e, CellBuffers&) {
    const HeatCell cell(model_, e, T);
    const auto nodes = cell.nodes;
    const int n = cell.n;
    const ReferenceTable& tab = cell.tab;
    const MaterialSpec& mat = cell.mat;
    const double* Te = cell.T;
    const HeatCapacity& cap = capacity_[model_.material_index(e)];
    const PointExpressions& ex = expressions_[omp_get_thread_num()];
    double ve[max_cell_nodes], dNdx[3 * max_cell_nodes];
    double o[max_cell_nodes] = {};
    for (int a = 0; a < n; ++a) ve[a] = v[nodes[a]];
    const std::span<const Vec3> xs = cell.xs();
    for (int q = 0; q < tab.n_points; ++q) {
      const double dv = physical_gradients(tab, q, xs, dNdx) * tab.weights[q];
      const double* N = &tab.N[static_cast<std::size_t>(q) * n];
      double Tq = 0, vq = 0;
      Vec3 g = Vec3::Zero(), gv = Vec3::Zero();
      for (int a = 0; a < n; ++a) {
        const Vec3 ga(dNdx[3 * a], dNdx[3 * a + 1], dNdx[3 * a + 2]);
        Tq += N[a] * Te[a];
        vq += N[a] * ve[a];
        g += ga * Te[a];
        gv += ga * ve[a];
      }
      const double k = mat.conductivity(Tq), dk = mat.conductivity.slope(Tq);
      double m = transient ? cap.rho_c(Tq) * inv_dt : 0.0;  // the N N terms
      if (source_of_T) {
        const Vec3 p = point_position(tab, q, xs);
        const double h = 1e-6 * std::max(1.0, std::abs(Tq));
        m -= theta *
             (ex.source(p.x(), p.y(), p.z(), t1, Tq + h) -
              ex.source(p.x(), p.y(), p.z(), t1, Tq - h)) /
             (2 * h);
      }
      for (int a = 0; a < n; ++a) {
        const Vec3 ga(dNdx[3 * a], dNdx[3 * a + 1], dNdx[3 * a + 2]);
        o[a] += (theta * (k * ga.dot(gv) + dk * vq * ga.dot(g)) + m * N[a] * vq) * dv;
      }
    }
    const auto& faces = model_.heat_faces();
    for (int i = model_.heat_face_start(e); i < model_.heat_face_start(e + 1); ++i) {
      const HeatFace& hf = faces[i];
      for_face_points(mesh, hf, [&](const double* N, int nf, double da, const Vec3& p) {
        double Tq = 0, vq = 0;
        for (int a = 0; a < nf; ++a) {
          Tq += N[a] * Te[hf.local[a]];
          vq += N[a] * ve[hf.local[a]];
        }
        const FaceFlux f = face_flux(spec_.boundary[hf.boundary], ex.value[hf.boundary],
                                     ex.ambient[hf.boundary], spec_, p, t1, Tq);
        for (int a = 0; a < nf; ++a) o[hf.local[a]] -= theta * f.dq_dT * N[a] * vq * da;
      });
    }
    for (int a = 0; a < n; ++a) out[nodes[a]] += o[a];
  };
  model_.heat_assembler().matrices(
      kernel, [](int, const double*) {}, system_->own_cells());
  model_.layout().sum(out, 1);
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
  return gmres(apply, precondition, dot, b, x, options, gmres_iterations_);
}

void HeatSolver::advance(double target) {
  const auto start = std::chrono::steady_clock::now();
  const bool own = !spec_.times.empty();
  const double t_end = own ? spec_.times[std::min(next_target_, spec_.times.size() - 1)] : target;
  if (own && next_target_ >= spec_.times.size())
    throw std::logic_error("heat: asked for a time after its last step");
  // Targets to reach, each with its cut-back depth (as the mechanical step control).
  std::vector<std::pair<double, int>> targets = {{t_end, 0}};
  // Crank–Nicolson (θ < 1) starts with two backward-Euler half steps (Rannacher, Numer. Math.
  // 43, 1984): θ near ½ damps hardly at all the oscillation that initial temperatures which do
  // not meet the boundary conditions (a sudden surface temperature) leave, and it costs its
  // order; a fixed number of first-order steps at the start keeps the second order.
  const bool rannacher = spec_.transient && spec_.theta < 1 && steps_ == 0;
  if (rannacher) targets.push_back({0.5 * (snapshots_.back().time + t_end), 0});
  theta_ = rannacher ? 1.0 : spec_.theta;
  while (!targets.empty()) {
    const auto [t1, depth] = targets.back();
    if (par::any(interrupt_requested()))
      throw Interrupted(fmt::format("interrupted in the heat step to t = {:g}", t1));
    HeatSnapshot to;
    std::string why;
    if (solve(snapshots_.back(), t1, to, why)) {
      snapshots_.push_back(std::move(to));
      targets.pop_back();
      ++steps_;
      log_.info("heat {:4d}  t = {:<10.6g} iterations {:3d}  residual {:.2e}{}", steps_, t1,
                last_iterations_, last_residual_,
                rannacher ? "  (Crank-Nicolson's backward-Euler start)" : "");
      continue;
    }
    const double t0 = snapshots_.back().time, mid = 0.5 * (t0 + t1);
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
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void HeatSolver::interpolate(double t, std::vector<double>* T, std::vector<double>& flow,
                             std::vector<double>& energy) const {
  const double eps = 1e-12 * std::max(1.0, std::abs(t));
  std::size_t i = snapshots_.size() - 1;
  while (i > 0 && snapshots_[i - 1].time >= t - eps) --i;
  // snapshots_[i] is the first at or after t.
  const HeatSnapshot& b = snapshots_[i];
  if (std::abs(b.time - t) <= eps || i == 0) {
    if (b.time > t + eps) throw std::logic_error("heat: asked for a time before its snapshots");
    if (T) *T = b.T;
    flow = b.flow;
    energy = b.energy;
    return;
  }
  const HeatSnapshot& a = snapshots_[i - 1];
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
  if (snapshots_.empty()) start();
  const double eps = 1e-12 * std::max(1.0, std::abs(t));
  while (snapshots_.back().time < t - eps) advance(t);
  std::vector<double> energy;
  interpolate(t, &T, flow, energy);
  // A transient's flows: the mean over [committed, t], from the heat brought in, exact over
  // any grid of heat steps (the energy is linear in time within a heat step).
  if (!spec_.transient || !(t > committed_ + eps)) return;
  std::vector<double> flow0, energy0;
  interpolate(committed_, nullptr, flow0, energy0);
  for (std::size_t k = 0; k < flow.size(); ++k)
    flow[k] = (energy[k] - energy0[k]) / (t - committed_);
}

void HeatSolver::committed(double t) {
  const double eps = 1e-12 * std::max(1.0, std::abs(t));
  committed_ = t;
  while (snapshots_.size() > 1 && snapshots_[1].time <= t + eps) snapshots_.pop_front();
}

HeatMemory HeatSolver::memory() const {
  HeatMemory mem;
  mem.snapshots = snapshots_;
  mem.R_last = R_last_;
  mem.S_last = S_last_;
  mem.committed = committed_;
  mem.steps = steps_;
  mem.iterations = iterations_;
  mem.gmres_iterations = gmres_iterations_;
  return mem;
}

void HeatSolver::resume(HeatMemory mem) {
  snapshots_ = std::move(mem.snapshots);
  R_last_ = std::move(mem.R_last);
  S_last_ = std::move(mem.S_last);
  committed_ = mem.committed;
  steps_ = mem.steps;
  iterations_ = mem.iterations;
  gmres_iterations_ = mem.gmres_iterations;
  // The heat section's own steps after the newest solution: those of the case now (a restart
  // may change them).
  next_target_ = 0;
  if (!snapshots_.empty()) {
    const double t = snapshots_.back().time, eps = 1e-12 * std::max(1.0, std::abs(t));
    while (next_target_ < spec_.times.size() && spec_.times[next_target_] <= t + eps)
      ++next_target_;
  }
}

// ---------------------------------------------------------------------------------------------

std::vector<double> nodal_heat_flux(const Model& model, const std::vector<double>& T) {
  const Mesh& mesh = model.mesh();
  // Per node the count of cells at it, then the sum of their fluxes there: each rank goes over
  // the cells whose points it holds, and the layout completes values and counts alike (as the
  // recovery of the stresses does).
  std::vector<double> sums(4 * static_cast<std::size_t>(mesh.n_nodes()), 0.0);
  double dN[3 * max_cell_nodes];
  for (int e = 0; e < mesh.cells.size(); ++e) {
    if (!model.holds_points(e)) continue;
    const auto nodes = mesh.cells.nodes(e);
    const int n = static_cast<int>(nodes.size());
    const CellType type = mesh.cells.type[e];
    const double* xi = node_coordinates(type);
    const MaterialSpec& mat = *model.material_of(e).spec;
    for (int a = 0; a < n; ++a) {
      shape_gradients(type, xi + 3 * a, dN);
      Mat3 J = Mat3::Zero();  // J(i, k) = dx_i / dξ_k
      for (int b = 0; b < n; ++b)
        for (int k = 0; k < 3; ++k) J.col(k) += mesh.x[nodes[b]] * dN[3 * b + k];
      if (!(J.determinant() > 0)) continue;
      const Mat3 Jinv_t = J.inverse().transpose();
      Vec3 g = Vec3::Zero();
      for (int b = 0; b < n; ++b)
        g += Jinv_t * Vec3(dN[3 * b], dN[3 * b + 1], dN[3 * b + 2]) * T[nodes[b]];
      const Vec3 qa = -mat.conductivity(T[nodes[a]]) * g;
      double* v = &sums[4 * static_cast<std::size_t>(nodes[a])];
      v[0] += 1;
      for (int d = 0; d < 3; ++d) v[1 + d] += qa[d];
    }
  }
  model.layout().sum(sums, 4);
  std::vector<double> q(3 * static_cast<std::size_t>(mesh.n_nodes()), 0.0);
  for (int m = 0; m < mesh.n_nodes(); ++m) {
    const double* v = &sums[4 * static_cast<std::size_t>(m)];
    if (v[0] > 0)
      for (int d = 0; d < 3; ++d) q[3 * m + d] = v[1 + d] / v[0];
  }
  return q;
}

}  // namespace hencky
