// The values of a converged step that the outputs report (step_values.hpp).
#include "output/step_values.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "fem/reference_element.hpp"
#include "material/elastic.hpp"
#include "parallel/mpi.hpp"

namespace hencky {

std::vector<Voigt> recover_nodal_stress(const Model& model, const State& state) {
  return recover_fields(model, state).nodal_stress;
}

namespace {
/// The shape functions of the probe's cell at the probe.
template <class F>
void at_probe(const Model& model, const Probe& probe, F&& f) {
  const auto& mesh = model.mesh();
  const auto nodes = mesh.cells.nodes(probe.cell);
  double N[max_cell_nodes];
  shape_values(mesh.cells.type[probe.cell], probe.xi, N);
  for (std::size_t a = 0; a < nodes.size(); ++a) f(N[a], nodes[a]);
}
}  // namespace

ProbeValues probe_values(const Model& model, const Probe& probe, const State& state,
                         const std::vector<Voigt>& nodal_stress,
                         std::span<const double> nodal_eps_p_eq) {
  ProbeValues v;
  at_probe(model, probe, [&](double N, int n) {
    v.displacement += N * Vec3(state.u[3 * n], state.u[3 * n + 1], state.u[3 * n + 2]);
    v.stress += N * nodal_stress[n];
    v.temperature += N * state.nodal_temperature[n];
    if (!nodal_eps_p_eq.empty()) v.equivalent_plastic_strain += N * nodal_eps_p_eq[n];
  });
  v.von_mises = von_mises(v.stress);
  return v;
}

ProbeValues probe_values(const Model& model, const Probe& probe, const State& state,
                         const RecoveredFields& f) {
  ProbeValues v = probe_values(model, probe, state, f.nodal_stress, f.nodal_eps_p_eq);
  at_probe(model, probe, [&](double N, int n) {
    v.strain += N * f.nodal_strain[n];
    v.elastic_strain += N * f.nodal_elastic_strain[n];
    v.thermal_strain += N * f.nodal_thermal_strain[n];
    if (!f.nodal_plastic_strain.empty()) v.plastic_strain += N * f.nodal_plastic_strain[n];
    if (!f.nodal_eps_ep.empty()) v.eps_ep += N * f.nodal_eps_ep[n];
  });
  const int n_law = model.law_state_size();
  v.internal.assign(n_law, 0.0);
  if (n_law > 0)
    at_probe(model, probe, [&](double N, int n) {
      for (int j = 0; j < n_law; ++j)
        v.internal[j] += N * f.nodal_internal[static_cast<std::size_t>(n) * n_law + j];
    });
  return v;
}

std::vector<Vec3> region_reactions(const Model& model, const State& state) {
  std::vector<Vec3> out;
  const Partition& part = model.partition();
  for (const auto& r : model.reaction_regions()) {
    if (!r.force) continue;
    Vec3 f = Vec3::Zero();
    for (int n : r.region->nodes) {
      if (part.node_owner[n] != part.rank) continue;  // another rank's share
      for (int d = 0; d < 3; ++d)
        f[d] += state.f_int[3 * n + d] - state.f_ext[3 * n + d] - state.f_contact[3 * n + d];
    }
    out.push_back(f);
  }
  return out;
}

std::vector<ContactTotals> contact_totals(const Model& model, const State& state) {
  std::vector<ContactTotals> out;
  for (std::size_t b = 0; b < model.contacts().size(); ++b)
    out.push_back(contact_totals(model.contacts()[b], state.contact[b], state.u));
  return out;
}

namespace {
/// f(x) for each number of a probe's values (a const or a mutable ProbeValues), in one fixed
/// order: for the sum over the ranks.
template <class V, class F>
void each_number(V& v, F&& f) {
  for (int d = 0; d < 3; ++d) f(v.displacement[d]);
  for (int c = 0; c < 6; ++c) f(v.stress[c]);
  f(v.von_mises);
  f(v.temperature);
  f(v.equivalent_plastic_strain);
  for (auto* e : {&v.strain, &v.elastic_strain, &v.plastic_strain, &v.thermal_strain})
    for (int c = 0; c < 6; ++c) f((*e)[c]);
  f(v.eps_ep);
  for (auto& x : v.internal) f(x);
}
}  // namespace

StepValues step_values(const Model& model, const State& state, const RecoveredFields& fields) {
  const Partition& part = model.partition();
  StepValues out;
  // Probes: the owner of the probe's cell evaluates, the others give zeros.
  const auto& probes = model.probes();
  std::vector<double> probe_numbers;
  for (const Probe& p : probes) {
    ProbeValues v = p.cell >= 0 && part.cell_owner[p.cell] == part.rank
                        ? probe_values(model, p, state, fields)
                        : ProbeValues{};
    v.internal.resize(model.law_state_size());  // zeros on the other ranks
    each_number(v, [&](double x) { probe_numbers.push_back(x); });
  }
  // Reactions and the contacts' sums (force, nodes, resultant) over each rank's own nodes; the
  // contacts' largest values over all.
  const std::vector<Vec3> reactions = region_reactions(model, state);
  const auto& bodies = model.contacts();
  std::vector<double> sums, largest;
  for (const Vec3& r : reactions) sums.insert(sums.end(), {r.x(), r.y(), r.z()});
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const ContactTotals t =
        contact_totals(bodies[b], state.contact[b], state.u, &part.node_owner, part.rank);
    sums.insert(sums.end(), {t.force, static_cast<double>(t.nodes), t.resultant.x(),
                             t.resultant.y(), t.resultant.z()});
    largest.insert(largest.end(), {t.max_penetration, t.max_penetration_relative, t.max_pressure});
  }
  sums.insert(sums.end(), probe_numbers.begin(), probe_numbers.end());
  // Over each rank's own nodes: the balance (reactions, loads, contact forces and Σ |F_int|,
  // the scale of the forces), and the largest nodal values, each as 5 numbers: the value, the
  // node's number and its position.
  double balance[10] = {};
  std::array<double, 15> mine;
  for (int k = 0; k < 3; ++k) mine[5 * k] = -1;
  const bool plastic = !fields.nodal_eps_p_eq.empty();
  const Mesh& mesh = model.mesh();
  for (int n = 0; n < mesh.n_nodes(); ++n) {
    if (part.node_owner[n] != part.rank) continue;
    const std::size_t i = 3 * static_cast<std::size_t>(n);
    for (int d = 0; d < 3; ++d) {
      balance[d] += state.f_int[i + d] - state.f_ext[i + d] - state.f_contact[i + d];
      balance[3 + d] += state.f_ext[i + d];
      balance[6 + d] += state.f_contact[i + d];
    }
    balance[9] += Vec3(state.f_int[i], state.f_int[i + 1], state.f_int[i + 2]).norm();
    const double v[3] = {von_mises(fields.nodal_stress[n]),
                         Vec3(state.u[i], state.u[i + 1], state.u[i + 2]).norm(),
                         plastic ? fields.nodal_eps_p_eq[n] : -1.0};
    for (int k = 0; k < 3; ++k)
      if (v[k] > mine[5 * k]) {
        mine[5 * k] = v[k];
        mine[5 * k + 1] = static_cast<double>(mesh.node_tag[n]);
        for (int d = 0; d < 3; ++d) mine[5 * k + 2 + d] = mesh.x[n][d];
      }
  }
  sums.insert(sums.end(), balance, balance + 10);
  par::sum_to_root(std::span<double>(sums));
  par::max_in_place(std::span<double>(largest));
  const double* s = sums.data();
  for (std::size_t k = 0; k < reactions.size(); ++k, s += 3)
    out.reactions.emplace_back(s[0], s[1], s[2]);
  for (std::size_t b = 0; b < bodies.size(); ++b, s += 5) {
    ContactTotals& t = out.contacts.emplace_back();
    t.force = s[0];
    t.nodes = static_cast<int>(std::lround(s[1]));
    t.resultant = Vec3(s[2], s[3], s[4]);
    t.max_penetration = largest[3 * b];
    t.max_penetration_relative = largest[3 * b + 1];
    t.max_pressure = largest[3 * b + 2];
  }
  out.probes.resize(probes.size());
  for (ProbeValues& v : out.probes) v.internal.resize(model.law_state_size());
  for (ProbeValues& v : out.probes) each_number(v, [&](double& x) { x = *s++; });
  out.balance = {Vec3(s[0], s[1], s[2]), Vec3(s[3], s[4], s[5]), Vec3(s[6], s[7], s[8]), s[9]};
  // The largest nodal values of all on root (the lowest rank's where two are equal).
  StepValues::Largest* best[3] = {&out.von_mises, &out.displacement, &out.eps_p_eq};
  const std::string bytes(reinterpret_cast<const char*>(mine.data()), sizeof mine);
  for (const std::string& b : par::gather_strings(bytes)) {
    if (b.size() != sizeof mine) continue;  // not root
    std::array<double, 15> theirs;
    std::memcpy(theirs.data(), b.data(), sizeof theirs);
    for (int k = 0; k < 3; ++k)
      if (theirs[5 * k] > best[k]->value) {
        best[k]->value = theirs[5 * k];
        best[k]->node = std::lround(theirs[5 * k + 1]);
        best[k]->x = Vec3(theirs[5 * k + 2], theirs[5 * k + 3], theirs[5 * k + 4]);
      }
  }
  return out;
}

HeatFlows heat_flows(const Model& model, const State& state) {
  HeatFlows out;
  const auto& bcs = model.spec().heat.boundary;
  const bool ignore_case = model.region_names_ignore_case();
  auto through = [&](const std::string& region, bool fixed_only) {
    double q = 0;
    for (std::size_t b = 0; b < bcs.size() && b < state.heat_flow.size(); ++b)
      if (Mesh::same_region_name(bcs[b].region, region, ignore_case) &&
          (!fixed_only || bcs[b].kind == HeatBoundarySpec::Kind::temperature))
        q += state.heat_flow[b];
    return q;
  };
  for (const auto& r : model.reaction_regions())
    if (r.heat) out.reactions.push_back(through(r.name, true));
  for (const auto& name : model.spec().output.heat_flows) out.flows.push_back(through(name, false));
  return out;
}

NodalContact nodal_contact(const Model& model, const State& state) {
  NodalContact out;
  const auto& bodies = model.contacts();
  if (bodies.empty()) return out;
  const int n = model.mesh().n_nodes();
  out.pressure.assign(n, 0.0);
  out.state.assign(n, 0.0);
  out.gap.assign(n, 0.0);
  std::vector<bool> seen(n, false);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    for (std::size_t i = 0; i < bodies[b].points.size(); ++i) {
      const ContactPoint& p = bodies[b].points[i];
      const ContactNode& s = state.contact[b][i];
      const double code = s.contact ? 1.0 : s.separation ? 2.0 : 0.0;
      out.state[p.node] = std::max(out.state[p.node], code);
      out.gap[p.node] = seen[p.node] ? std::min(out.gap[p.node], s.gap) : s.gap;
      seen[p.node] = true;
      if (s.contact)
        out.pressure[p.node] +=
            contact_force(s, contact_position(p, state.u)).dot(s.normal) / p.area;
    }
  return out;
}

double StepValues::Balance::imbalance() const {
  // Σ|F_int| is the scale where the loads vanish and the reactions are round-off.
  const double scale = std::max({supports.norm(), loads.norm(), contact.norm(), force_scale});
  return scale > 0 ? (supports + loads + contact).norm() / scale : 0.0;
}

}  // namespace hencky
