#include "solve/element_matrix.hpp"

#include "fem/reference_element.hpp"

namespace hencky {

void element_matrix(const Model& m, const State& trial, const std::vector<Tangent>& tangents,
                    const std::vector<Vec3>& config, const std::vector<Voigt>* initial_stress,
                    int e, CellBuffers& b) {
  const auto& mesh = m.mesh();

  const auto nodes = mesh.cells.nodes(e);
  const int n = static_cast<int>(nodes.size());
  const int nd = 3 * n;
  const bool plastic = m.material_of(e).plastic();
  const Tangent elastic;
  Vec3 x[max_cell_nodes], bv[max_cell_nodes];
  for (int a = 0; a < n; ++a) x[a] = config[nodes[a]];
  CellKinematics& kin = thread_kinematics();
  kin.compute(reference_table(mesh.cells.type[e]), std::span<const Vec3>(x, n));
  for (int q = 0; q < kin.points; ++q) {
    const double w = kin.dv[q];
    const double* dNdx = kin.grad(q);
    const int p = m.point_offset(e) + q;
    const ElasticConstants& k = trial.constants[p];
    // C = D + dev_scale·2G·I_dev + coef·v vᵀ (material/plastic_point.hpp): an isotropic
    // part and, for plastic points, a rank-one part.
    const Tangent& t = plastic ? tangents[p] : elastic;
    const double lam = t.lambda(k) * w, mu = t.mu(k) * w;
    if (t.coef != 0) {
      // B_aᵀv per node; K_ab += coef·(B_aᵀv)(B_bᵀv)ᵀ.
      const Voigt& v = t.v;
      for (int a = 0; a < n; ++a) {
        const double* g = dNdx + 3 * a;
        bv[a] =
            Vec3(g[0] * v[0] + g[2] * v[4] + g[1] * v[5], g[1] * v[1] + g[2] * v[3] + g[0] * v[5],
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
    // K_ab = B_aᵀ D B_b for isotropic D: λ g_a g_bᵀ + μ (g_b g_aᵀ + (g_a·g_b) I); with an
    // initial stress σ0 also (g_a·σ0 g_b) I.
    const Mat3 s0 = initial_stress ? Mat3(stress_tensor((*initial_stress)[p]) * w) : Mat3::Zero();
    for (int a = 0; a < n; ++a) {
      const Vec3 ga(dNdx[3 * a], dNdx[3 * a + 1], dNdx[3 * a + 2]);
      const Vec3 s0ga = s0 * ga;
      for (int bb = a; bb < n; ++bb) {
        const Vec3 gb(dNdx[3 * bb], dNdx[3 * bb + 1], dNdx[3 * bb + 2]);
        const double dot = mu * ga.dot(gb) + s0ga.dot(gb);
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
}

}  // namespace hencky
