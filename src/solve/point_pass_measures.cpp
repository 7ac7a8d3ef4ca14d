// The measures of a point pass (solve/point_pass.hpp): the report's Δ^σ and Δ^ε, the yield
// excess σ̃/σ̃_y − 1 of each point (the admissibility of an iterate) and its largest, and the
// warnings about the curves after a converged step.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "fem/reference_element.hpp"
#include "parallel/mpi.hpp"
#include "solve/point_pass.hpp"

namespace hencky {

void PointPass::measure_excess(const MaterialModel& mat, const State& c, State& trial, int p,
                               const Voigt& law_stress) {
  const double y = scheme_.yield_stress(point_step_[p], trial.eps_p_eq[p], trial.eps_ep[p],
                                        trial.eps_ep_max[p]);
  const Voigt s = mat.law->relative_stress(law_stress, law_state(c, trial, p).now);
  excess_[p] = y > 0 ? von_mises(s) / y - 1 : (von_mises(s) > 0 ? INFINITY : -1.0);
}

/// Δ^σ and Δ^ε of the report, made global: the volume-weighted root mean square of the
/// points' numerators over that of σ̃ (resp. ε̃^{e+p}) over the plastic materials.
void PointPass::measures(const State& trial, PointPassResult& r) const {
  double ns = 0, ds = 0, ne = 0, de = 0;
  int n_plastic = 0, n_broken = 0;
  for_plastic_points([&](int p) {
    const double w = point_volume_[p], q = von_mises(trial.stress[p]);
    ns += w * defect_sigma_[p] * defect_sigma_[p];
    ds += w * q * q;
    ne += w * defect_eps_[p] * defect_eps_[p];
    de += w * trial.eps_ep[p] * trial.eps_ep[p];
    n_plastic += trial.flowing[p];
    n_broken += point_iter_[p].breaks_hold;
    r.yield_excess = std::max(r.yield_excess, excess_[p]);
    r.points_above += excess_[p] > YieldExcess::slack;
  });
  double sums[6] = {ns, ds, ne, de, static_cast<double>(n_plastic), static_cast<double>(n_broken)};
  par::sum_in_place(std::span<double>(sums));
  ns = sums[0], ds = sums[1], ne = sums[2], de = sums[3];
  n_plastic = static_cast<int>(sums[4]);
  r.holds_broken = static_cast<int>(sums[5]);
  r.delta_sigma = ds > 0 ? std::sqrt(ns / ds) : 0.0;
  r.delta_eps = de > 0 ? std::sqrt(ne / de) : 0.0;
  r.plastic_points = n_plastic;
  par::max_in_place(std::span<double>(&r.yield_excess, 1));
  r.points_above = static_cast<int>(par::sum(static_cast<long long>(r.points_above)));
}

namespace {
/// The largest of value(p) over the points p that `each` visits on this rank (each(f) calls
/// f(p) for them), with its point's place, the same on every rank. Collective.
template <class Each, class Value>
PointLargest largest_at_points(const Model& m, Each&& each, Value&& value) {
  // This rank's largest: value, node, position (the point in the undeformed mesh).
  std::array<double, 5> mine = {-INFINITY, 0, 0, 0, 0};
  const auto& mesh = m.mesh();
  each([&](int p) {
    const double v = value(p);
    if (!(v > mine[0])) return;
    mine[0] = v;
    mine[4] = p;  // the point, placed below
  });
  if (mine[0] > -INFINITY) {
    const int p = static_cast<int>(mine[4]);
    int e = 0;
    while (m.point_offset(e + 1) <= p) ++e;
    const auto nodes = mesh.cells.nodes(e);
    const ReferenceTable& tab = reference_table(mesh.cells.type[e]);
    const double* N = &tab.N[static_cast<std::size_t>(p - m.point_offset(e)) * tab.n_nodes];
    Vec3 x = Vec3::Zero();
    for (std::size_t a = 0; a < nodes.size(); ++a) x += N[a] * mesh.x[nodes[a]];
    int nearest = nodes[0];
    for (int n : nodes)
      if ((mesh.x[n] - x).norm() < (mesh.x[nearest] - x).norm()) nearest = n;
    mine = {mine[0], static_cast<double>(mesh.node_tag[nearest]), x.x(), x.y(), x.z()};
  }
  // The largest over the ranks (the lowest rank's where two are equal), on every rank.
  std::array<double, 5> best = mine;
  const std::string bytes(reinterpret_cast<const char*>(mine.data()), sizeof mine);
  for (const std::string& b : par::gather_strings(bytes)) {
    if (b.size() != sizeof mine) continue;
    std::array<double, 5> theirs;
    std::memcpy(theirs.data(), b.data(), sizeof theirs);
    if (theirs[0] > best[0]) best = theirs;
  }
  par::broadcast(std::span<double>(best));
  PointLargest y;
  y.value = best[0];
  y.node = std::lround(best[1]);
  y.x = Vec3(best[2], best[3], best[4]);
  return y;
}
}  // namespace

YieldExcess PointPass::largest_excess() const {
  YieldExcess y;
  static_cast<PointLargest&>(y) = largest_at_points(
      m_, [&](auto&& f) { for_plastic_points(f); }, [&](int p) { return excess_[p]; });
  return y;
}

PointLargest PointPass::largest_von_mises(const State& s) const {
  const auto each = [&](auto&& f) {
    for (int e = 0; e < m_.mesh().cells.size(); ++e)
      if (mine(e))
        for (int p = m_.point_offset(e); p < m_.point_offset(e + 1); ++p) f(p);
  };
  return largest_at_points(m_, each, [&](int p) { return von_mises(s.stress[p]); });
}

/// Warnings about the curves after a converged step: temperatures outside their tables,
/// plastic strains beyond their last point. Collective.
void PointPass::check_curves(const State& s, Log& log) const {
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
      mat.hardening->warn_outside(mat.spec->name, t_min[k], t_max[k], e_max[k], log);
}

}  // namespace hencky
