#include "solve/element_matrix.hpp"

#include "fem/hencky_strain.hpp"
#include "fem/reference_element.hpp"

namespace hencky {
namespace {

/// B̄ᵀCB̄ of one point into the upper blocks (b ≥ a) of ke (nd × nd): gradients dNdx, B-bar
/// corrections corr (nullptr: none), C = D + dev_scale·2G·I_dev + coef·v vᵀ of the tangent t
/// (material/plastic_point.hpp) at constants k, weight w. With F (the updated Lagrangian step,
/// whose B̄_L = B̄·Fᵀ) each block is F·K_ab·Fᵀ: every term of K_ab is an outer product u_a w_bᵀ
/// of per-node vectors, or a multiple of I, so the vectors are turned by F and I becomes FFᵀ.
void add_material_part(int n, const double* dNdx, const double* corr, const Tangent& t,
                       const ElasticConstants& k, double w, const Mat3* F, double* ke) {
  const int nd = 3 * n;
  const auto turn = [&](const Vec3& v) { return F ? Vec3(*F * v) : v; };
  Vec3 bv[max_cell_nodes], dv[max_cell_nodes];
  const double lam = t.lambda(k) * w, mu = t.mu(k) * w;
  if (t.coef != 0) {
    // B_aᵀv per node; K_ab += coef·(B_aᵀv)(B_bᵀv)ᵀ.
    const Voigt& v = t.v;
    for (int a = 0; a < n; ++a) {
      const double* g = dNdx + 3 * a;
      bv[a] = turn(Vec3(g[0] * v[0] + g[2] * v[4] + g[1] * v[5],
                        g[1] * v[1] + g[2] * v[3] + g[0] * v[5],
                        g[2] * v[2] + g[1] * v[3] + g[0] * v[4]));
    }
    const double cw = t.coef * w;
    for (int a = 0; a < n; ++a)
      for (int bb = a; bb < n; ++bb)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            ke[(3 * a + i) * nd + 3 * bb + j] += cw * bv[a][i] * bv[bb][j];
  }
  if (corr) {
    // B̄_a = B_a + (1/3) m d_aᵀ: K_ab gains (1/3)(B_aᵀCm) d_bᵀ + (1/3) d_a (B_bᵀCm)ᵀ
    // + (1/9)(mᵀCm) d_a d_bᵀ, with Cm = C·(1, 1, 1, 0, 0, 0).
    Voigt m_vec;
    m_vec << 1, 1, 1, 0, 0, 0;
    const Voigt cm = t.times(k, m_vec) * w;
    const double mcm = (cm[0] + cm[1] + cm[2]) / 9;
    for (int a = 0; a < n; ++a) {
      const double* g = dNdx + 3 * a;
      bv[a] = turn(Vec3(g[0] * cm[0] + g[2] * cm[4] + g[1] * cm[5],
                        g[1] * cm[1] + g[2] * cm[3] + g[0] * cm[5],
                        g[2] * cm[2] + g[1] * cm[3] + g[0] * cm[4]) /
                   3);
      dv[a] = turn(Vec3(corr[3 * a], corr[3 * a + 1], corr[3 * a + 2]));
    }
    for (int a = 0; a < n; ++a)
      for (int bb = a; bb < n; ++bb)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            ke[(3 * a + i) * nd + 3 * bb + j] +=
                bv[a][i] * dv[bb][j] + dv[a][i] * bv[bb][j] + mcm * dv[a][i] * dv[bb][j];
  }
  // K_ab = B_aᵀ D B_b for isotropic D: λ g_a g_bᵀ + μ (g_b g_aᵀ + (g_a·g_b) I).
  const Mat3 ffT = F ? Mat3(*F * F->transpose()) : Mat3::Identity();
  for (int a = 0; a < n; ++a) {
    const Vec3 ga0(dNdx[3 * a], dNdx[3 * a + 1], dNdx[3 * a + 2]), ga = turn(ga0);
    for (int bb = a; bb < n; ++bb) {
      const Vec3 gb0(dNdx[3 * bb], dNdx[3 * bb + 1], dNdx[3 * bb + 2]), gb = turn(gb0);
      const double dot = mu * ga0.dot(gb0);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const double identity = F ? dot * ffT(i, j) : (i == j ? dot : 0.0);
          ke[(3 * a + i) * nd + 3 * bb + j] += lam * ga[i] * gb[j] + mu * gb[i] * ga[j] + identity;
        }
    }
  }
}

/// F·(B̄ᵀCB̄)·Fᵀ of one point for a general C (6 × 6, engineering shears on the strain side)
/// into the upper blocks of ke: with BL_a = B̄_a Fᵀ (6 × 3), K_ab += w·BL_aᵀ C BL_b.
void add_material_matrix(int n, const double* dNdx, const double* corr, const Mat6& c, double w,
                         const Mat3& F, double* ke) {
  const int nd = 3 * n;
  using Mat63 = Eigen::Matrix<double, 6, 3>;
  Mat63 bl[max_cell_nodes], cbl[max_cell_nodes];
  for (int a = 0; a < n; ++a) {
    const double gx = dNdx[3 * a], gy = dNdx[3 * a + 1], gz = dNdx[3 * a + 2];
    Mat63 b = Mat63::Zero();
    b(0, 0) = gx, b(1, 1) = gy, b(2, 2) = gz;
    b(3, 1) = gz, b(3, 2) = gy;
    b(4, 0) = gz, b(4, 2) = gx;
    b(5, 0) = gy, b(5, 1) = gx;
    if (corr)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) b(i, j) += corr[3 * a + j] / 3;
    bl[a] = b * F.transpose();
    cbl[a] = w * c * bl[a];
  }
  for (int a = 0; a < n; ++a)
    for (int bb = a; bb < n; ++bb) {
      const Mat3 k = bl[a].transpose() * cbl[bb];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) ke[(3 * a + i) * nd + 3 * bb + j] += k(i, j);
    }
}

/// The tangent of the updated Lagrangian step (CellDeformation) at the iterate `trial` from
/// the step's start `start`: per point F·(B̄ᵀCB̄ at the corrected gradients)·Fᵀ, C = dS/dE of
/// Hencky's strain for the scheme's matrix dτ/dΔε (HenckyStep::tangent), and the
/// initial-stress part ∫(∇N_a·S∇N_b) I of the iterate's S, with for
/// B-bar cells the second variation of the mean trace. This is the derivative of
/// CellDeformation::add_force when C is: newton's matrix is consistent, and symmetric.
void updated_matrix(const Model& m, const StepStart& step_start, const State& trial,
                    const std::vector<Tangent>& tangents, const CellKinematics& kin,
                    std::span<const int> nodes, int e, CellBuffers& b) {
  const int n = kin.n, nd = 3 * n;
  const bool plastic = m.material_of(e).plastic();
  const Tangent elastic;
  const State& start = step_start.state;
  double du[3 * max_cell_nodes];
  for (int a = 0; a < n; ++a)
    for (int d = 0; d < 3; ++d)
      du[3 * a + d] =
          step_start.at_start ? 0.0 : trial.u[3 * nodes[a] + d] - start.u[3 * nodes[a] + d];
  CellDeformation& def = thread_deformation();
  def.compute(kin, du);
  const State& stressed = step_start.at_start ? start : trial;
  double gg_mean[max_cell_nodes][max_cell_nodes] = {};  // the mean of g_a·g_b (B-bar)
  double p_mean = 0;
  for (int q = 0; q < kin.points; ++q) {
    const double w = kin.dv[q];
    const double* g = kin.grad(q);
    const int p = m.point_offset(e) + q;
    const double j_t = step_start.volume_ratio[p];
    // S of the iterate's Kirchhoff stress τ = Jσ in the frame of x, as the forces take it
    // (PointPass::update): U⁻¹τ̂U⁻¹/J(t) of the (B-bar) C̄.
    HenckyStep hencky;
    hencky.start(start.constants[p].compliance() * (j_t * start.stress[p]));
    hencky.increment(def.E[q]);
    const Voigt tau = rotate_stress(def.rotation(q).transpose(),
                                    (j_t * def.J[q]) * stressed.stress[p]);
    const Voigt S = hencky.second_piola(tau, j_t);
    if (step_start.matrix != UpdatedMatrix::exact) {
      add_material_part(n, g, kin.bbar ? def.corr(q) : nullptr, plastic ? tangents[p] : elastic,
                        trial.constants[p], w, &def.F[q], b.ke);
    } else {
      const ElasticConstants& k = trial.constants[p];
      const Mat6 c = hencky.tangent(S, plastic ? tangents[p].matrix(k) : k.stiffness(), j_t);
      add_material_matrix(n, g, kin.bbar ? def.corr(q) : nullptr, c, w, def.F[q], b.ke);
    }
    if (step_start.matrix == UpdatedMatrix::law_without_stress) continue;
    // The initial-stress part (∇N_a·S∇N_b) I of the iterate's S.
    const Mat3 s = stress_tensor(S) * w;
    const double pw = w * (S[0] + S[1] + S[2]) / 3;
    p_mean += pw;
    for (int a = 0; a < n; ++a) {
      const Vec3 ga(g[3 * a], g[3 * a + 1], g[3 * a + 2]);
      const Vec3 sga = s * ga;
      for (int bb = a; bb < n; ++bb) {
        const Vec3 gb(g[3 * bb], g[3 * bb + 1], g[3 * bb + 2]);
        double geo = sga.dot(gb);
        if (kin.bbar) {
          const double gg = ga.dot(gb);
          geo -= pw * gg;
          gg_mean[a][bb] += w * gg;
        }
        for (int i = 0; i < 3; ++i) b.ke[(3 * a + i) * nd + 3 * bb + i] += geo;
      }
    }
  }
  if (kin.bbar)  // Σ_q w_q p_q · mean(g_a·g_b): the mean trace's second variation
    for (int a = 0; a < n; ++a)
      for (int bb = a; bb < n; ++bb)
        for (int i = 0; i < 3; ++i)
          b.ke[(3 * a + i) * nd + 3 * bb + i] += p_mean * gg_mean[a][bb] / kin.volume;
}

}  // namespace

void element_matrix(const Model& m, const State& trial, const std::vector<Tangent>& tangents,
                    const std::vector<Vec3>& config, const StepStart* start, int e,
                    CellBuffers& b) {
  const auto& mesh = m.mesh();
  const auto nodes = mesh.cells.nodes(e);
  const int n = static_cast<int>(nodes.size());
  const int nd = 3 * n;
  const bool plastic = m.material_of(e).plastic();
  const Tangent elastic;
  Vec3 x[max_cell_nodes];
  for (int a = 0; a < n; ++a) x[a] = config[nodes[a]];
  CellKinematics& kin = thread_kinematics();
  kin.compute(reference_table(mesh.cells.type[e]), std::span<const Vec3>(x, n));
  if (start) {
    updated_matrix(m, *start, trial, tangents, kin, nodes, e, b);
  } else {
    for (int q = 0; q < kin.points; ++q) {
      const int p = m.point_offset(e) + q;
      add_material_part(n, kin.grad(q), kin.bbar ? kin.corr(q) : nullptr,
                        plastic ? tangents[p] : elastic, trial.constants[p], kin.dv[q], nullptr,
                        b.ke);
    }
  }
  // Lower blocks by symmetry.
  for (int a = 0; a < n; ++a)
    for (int bb = a + 1; bb < n; ++bb)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          b.ke[(3 * bb + j) * nd + 3 * a + i] = b.ke[(3 * a + i) * nd + 3 * bb + j];
}

}  // namespace hencky
