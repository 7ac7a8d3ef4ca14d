// The heat analysis's passes over the cells (solve/heat.hpp): G and its matrix (evaluate), the
// product of the whole dG/dT with a vector (jacobian_times), and the natural conditions'
// flows (natural_flows).
#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <mutex>

#include "parallel/mpi.hpp"
#include "parallel/nodal_layout.hpp"
#include "solve/heat_terms.hpp"

namespace hencky {

using heat_terms::face_flux;
using heat_terms::FaceFlux;
using heat_terms::for_face_points;
using heat_terms::heat_degree;

namespace {

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

/// What evaluate()'s cell terms read besides the cell: the step's constants.
struct StepConstants {
  const HeatSpec& spec;
  const std::vector<double>& T0;  ///< the nodal temperatures at the step's start
  double t1;                      ///< the step's end
  double theta;                   ///< θ of the step (1 for a steady analysis)
  double inv_dt;                  ///< 1/Δt (0 for a steady analysis)
  bool source;                    ///< a source that is not zero
  bool matrix;                    ///< the matrix is wanted (into the cell's ke)
};

/// One cell's share of R and C and their scales, per node of the cell.
struct CellTerms {
  double r[max_cell_nodes] = {}, sr[max_cell_nodes] = {}, c[max_cell_nodes] = {},
         sc[max_cell_nodes] = {};
};

/// The volume terms of a cell, point by point: conduction, the source and (transient) the
/// capacity, into `out` and (when st.matrix) the matrix ke (n × n). Throws InputError for a
/// source that is not finite.
void volume_terms(const HeatCell& cell, const HeatCapacity& cap, const Expression& source,
                  const StepConstants& st, CellTerms& out, double* ke) {
  const auto nodes = cell.nodes;
  const int n = cell.n;
  const ReferenceTable& tab = cell.tab;
  const MaterialSpec& mat = cell.mat;
  const double* Te = cell.T;
  const HeatSpec& spec = st.spec;
  const bool matrix = st.matrix;
  const double theta = st.theta, t1 = st.t1;
  double* r = out.r;
  double* sr = out.sr;
  double* c = out.c;
  double* sc = out.sc;
  double T0e[max_cell_nodes], dNdx[3 * max_cell_nodes];
  for (int a = 0; a < n; ++a) T0e[a] = st.T0[nodes[a]];
  const std::span<const Vec3> xs = cell.xs();
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
    if (st.source) {
      const Vec3 p = point_position(tab, q, xs);
      const double Q = source(p.x(), p.y(), p.z(), t1, Tq);
      if (!std::isfinite(Q))
        throw InputError(spec.source.where(),
                         fmt::format("source: \"{}\" gives {:g} at ({:g}, {:g}, {:g}), t = "
                                     "{:g}, T = {:g}; expected a finite value",
                                     spec.source.text(), Q, p.x(), p.y(), p.z(), t1, Tq));
      double m = 0;  // the matrix's −∂Q/∂T, where it is >= 0
      if (matrix && spec.source.depends_on_temperature()) {
        const double h = 1e-6 * std::max(1.0, std::abs(Tq));
        const double dQ =
            (source(p.x(), p.y(), p.z(), t1, Tq + h) - source(p.x(), p.y(), p.z(), t1, Tq - h)) /
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
    if (spec.transient) {
      const double H = cap.enthalpy(Tq), H0 = cap.enthalpy(T0q);
      const double m = cap.rho_c(Tq) * st.inv_dt;
      for (int a = 0; a < n; ++a) {
        c[a] += (H - H0) * N[a] * dv;
        sc[a] += (std::abs(H) + std::abs(H0)) * N[a] * dv;
        if (matrix && m > 0)
          for (int bb = 0; bb < n; ++bb) ke[a * n + bb] += m * N[a] * N[bb] * dv;
      }
    }
  }
}

/// The terms of cell e's faces with a flux, convection or radiation condition, into `out` and
/// (when st.matrix) ke. Throws InputError for a value of a condition that cannot be used.
void face_terms(const Model& model, int e, const HeatCell& cell, const HeatExpressions& ex,
                const StepConstants& st, CellTerms& out, double* ke) {
  const int n = cell.n;
  const double* Te = cell.T;
  const auto& faces = model.heat_faces();
  for (int i = model.heat_face_start(e); i < model.heat_face_start(e + 1); ++i) {
    const HeatFace& hf = faces[i];
    const HeatBoundarySpec& bc = st.spec.boundary[hf.boundary];
    for_face_points(model.mesh(), hf, [&](const double* N, int nf, double da, const Vec3& p) {
      double Tq = 0;
      for (int a = 0; a < nf; ++a) Tq += N[a] * Te[hf.local[a]];
      const FaceFlux f =
          face_flux(bc, ex.value[hf.boundary], ex.ambient[hf.boundary], st.spec, p, st.t1, Tq);
      for (int a = 0; a < nf; ++a) {
        const int la = hf.local[a];
        out.r[la] -= f.q * N[a] * da;
        out.sr[la] += f.scale * N[a] * da;
        if (st.matrix && f.dq_dT < 0)
          for (int bb = 0; bb < nf; ++bb)
            ke[la * n + hf.local[bb]] -= st.theta * f.dq_dT * N[a] * N[bb] * da;
      }
    });
  }
}

}  // namespace

void HeatSolver::evaluate(const std::vector<double>& T, const HeatSnapshot& from, double t1,
                          bool matrix, Evaluation& ev) {
  const int n_nodes = model_.mesh().n_nodes();
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
  const StepConstants st{spec_, from.T, t1, theta, inv_dt, source, matrix};
  std::exception_ptr error;
  std::mutex error_mutex;

  // Cells of one colour share no node, and the assembler runs the kernel colour by colour:
  // the kernel adds its cell's vectors into the nodal sums itself.
  auto kernel = [&](int e, CellBuffers& b) {
    try {
      const HeatCell cell(model_, e, T);
      const HeatExpressions& ex = expressions_[omp_get_thread_num()];
      CellTerms terms;
      volume_terms(cell, capacity_[model_.material_index(e)], ex.source, st, terms, b.ke);
      face_terms(model_, e, cell, ex, st, terms, b.ke);
      for (int a = 0; a < cell.n; ++a) {
        const int node = cell.nodes[a];
        R[node] += terms.r[a];
        SR[node] += terms.sr[a];
        C[node] += terms.c[a];
        SC[node] += terms.sc[a];
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
  // The nodal flows (nodal_flux) at t1, each node's once over the ranks, whose vectors the sum
  // below adds: by its owner on a distributed mesh, by root where every rank holds the whole.
  if (model_.layout().kind() != NodalLayout::Kind::replicated || par::root())
    for (const auto& [n, b] : model_.heat_nodal()) {
      const double q = nodal_flow(b, n, t1);
      R[n] -= q;
      SR[n] += std::abs(q);
    }
  model_.layout().sum_blocks(sums, 4);
  ev.R.assign(R, R + n_nodes);
  ev.SR.assign(SR, SR + n_nodes);
  ev.C.assign(C, C + n_nodes);
  ev.SC.assign(SC, SC + n_nodes);
  ev.G.resize(n_nodes);
  ev.S.resize(n_nodes);
  for (int i = 0; i < n_nodes; ++i) {
    if (transient) {
      ev.G[i] = ev.C[i] * inv_dt + theta * ev.R[i] + (1 - theta) * mem_.R_last[i];
      ev.S[i] = ev.SC[i] * inv_dt + theta * ev.SR[i] + (1 - theta) * mem_.S_last[i];
    } else {
      ev.G[i] = ev.R[i];
      ev.S[i] = ev.SR[i];
    }
  }
}

double HeatSolver::nodal_flow(int boundary, int node, double t) const {
  const Vec3& x = model_.mesh().x[node];
  const HeatBoundarySpec& bc = spec_.boundary[boundary];
  return bc.value.eval_checked(x.x(), x.y(), x.z(), t, "nodal_flux");
}

void HeatSolver::natural_flows(const std::vector<double>& T, double t,
                               std::vector<double>& q) const {
  const Mesh& mesh = model_.mesh();
  const HeatExpressions& ex = expressions_[0];
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
  for (const auto& [n, b] : model_.heat_nodal()) q[b] += nodal_flow(b, n, t);
  model_.layout().total(q);  // a distributed mesh's outer faces are each on one part
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
    const HeatExpressions& ex = expressions_[omp_get_thread_num()];
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

}  // namespace hencky
