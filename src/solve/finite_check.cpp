#include "solve/finite_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <type_traits>

#include "parallel/mpi.hpp"

namespace hencky {

bool all_finite(const State& s) {
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
         finite(s.f_contact) && finite(s.internal);
}

void throw_not_finite(const Model& m, const State& s, int iteration, double residual) {
  const auto& mesh = m.mesh();
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
    // The first dof: the model's index where the mesh is whole on every rank; on a part, as
    // the mesh file numbers it, 3 × tag + direction (a part's indices are its own).
    const long long i = first_dof(v);
    long long code = i;
    if (m.part() && i != LLONG_MAX) code = 3LL * mesh.node_tag[i / 3] + i % 3;
    code = par::min(code);
    if (code == LLONG_MAX) return;
    const long tag = m.part() ? static_cast<long>(code / 3) : mesh.node_tag[code / 3];
    throw SolveError(fmt::format("a NaN or an infinity appeared in the {} at node {} ({}) {}: {}",
                                 what, tag, "xyz"[code % 3], when, why));
  };
  at_node("external forces", s.f_ext);
  at_node("displacement", s.u);
  // Points: the first cell, and whether its stress (code 0) or its plastic state (1) is bad.
  long long cell_code = LLONG_MAX;
  for (int e = 0; e < mesh.cells.size() && cell_code == LLONG_MAX; ++e)
    for (int p = m.point_offset(e); p < m.point_offset(e + 1); ++p) {
      const bool stress = !s.stress[p].allFinite() || !std::isfinite(s.temperature[p]);
      if (stress || !s.plastic_strain[p].allFinite() || !std::isfinite(s.eps_p_eq[p]) ||
          !std::isfinite(s.eps_ep[p])) {
        cell_code = 2LL * m.agreed_index(e) + (stress ? 0 : 1);
        break;
      }
    }
  if (const long long cc = par::min(cell_code); cc != LLONG_MAX) {
    const Model::CellFacts e = m.cell_facts(static_cast<int>(cc / 2));
    throw SolveError(
        fmt::format("a NaN or an infinity appeared in the {} at element {} (material '{}') {}: {}",
                    cc % 2 == 0 ? "stress" : "plastic strain", e.tag,
                    m.materials()[e.material].spec->name, when, why));
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
  throw SolveError(
      fmt::format("the relative residual is {} {}: the {} at node {} is {:g}, too large to measure "
                  "(its square overflows): {}",
                  residual, when, what, mesh.node_tag[at / 3], largest, why));
}

}  // namespace hencky
