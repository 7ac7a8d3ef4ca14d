#pragma once
// The values of a converged step that the outputs report, from its state and its recovered
// fields: probes, reactions, heat flows, contact totals and fields, the largest nodal values and
// the balance of forces (history.csv, summary.json; results.hpp writes them).
#include <span>
#include <vector>

#include "solve/analysis.hpp"
#include "solve/recovery.hpp"

namespace hencky {

/// Nodal stress recovered from the integration points (recover_fields, solve/recovery.hpp):
/// each cell extrapolates its point values to its nodes, nodes average over their cells.
/// Collective on several ranks, like recover_fields.
std::vector<Voigt> recover_nodal_stress(const Model& model, const State& state);

struct ProbeValues {
  Vec3 displacement = Vec3::Zero();
  Voigt stress = Voigt::Zero();
  double von_mises = 0;
  double temperature = 0;
  double equivalent_plastic_strain = 0;
  /// Engineering shears; zero where the fields were not given (the overload without them).
  Voigt strain = Voigt::Zero(), elastic_strain = Voigt::Zero(), plastic_strain = Voigt::Zero(),
        thermal_strain = Voigt::Zero();
  double eps_ep = 0;  ///< ε̃^{e+p}
  /// The point law's internal variables (Model::law_variables), in its state's order.
  std::vector<double> internal;
};
ProbeValues probe_values(const Model& model, const Probe& probe, const State& state,
                         const std::vector<Voigt>& nodal_stress,
                         std::span<const double> nodal_eps_p_eq = {});
/// Every value of a probe, the strains included, from the recovered fields.
ProbeValues probe_values(const Model& model, const Probe& probe, const State& state,
                         const RecoveredFields& fields);

/// Reaction of each region of output.reactions: Σ over its nodes of (F_int − F_ext −
/// F_contact); on several ranks this rank's share, over the nodes it owns (step_values sums).
std::vector<Vec3> region_reactions(const Model& model, const State& state);

/// Heat into the body (W) through each region of output.reactions with a temperature condition
/// (reaction.<region>.heat), then through each region of output.heat_flows
/// (heat_flow.<region>): the sums of the flows of the heat.boundary entries that name it.
struct HeatFlows {
  std::vector<double> reactions, flows;
};
HeatFlows heat_flows(const Model& model, const State& state);

/// contact_totals (contact/contact.hpp) of every contact of the model, in case order.
std::vector<ContactTotals> contact_totals(const Model& model, const State& state);

/// Nodal contact fields: pressure (normal force over the tributary area), state (0 free,
/// 1 contact, 2 separating) and gap (signed distance from the surface; 0 off the contact
/// regions). Empty vectors without contact.
struct NodalContact {
  std::vector<double> pressure, state, gap;
};
NodalContact nodal_contact(const Model& model, const State& state);

/// The values of a converged step that history.csv and summary.json report: each probe
/// evaluated by the rank that owns its cell, each reaction and contact total summed (largest
/// values: the largest) over the nodes each rank owns, and gathered on root. Collective; on the
/// other ranks the result is not complete.
struct StepValues {
  std::vector<ProbeValues> probes;
  std::vector<Vec3> reactions;
  std::vector<ContactTotals> contacts;
  /// The largest value of a nodal field and its node (file number and undeformed position).
  struct Largest {
    double value = -1;  ///< < 0: the field is not there (no plasticity)
    long node = 0;
    Vec3 x = Vec3::Zero();
  };
  /// Of the recovered nodal fields written to the VTU files: the von Mises stress, |u| and ε̃p.
  Largest von_mises, displacement, eps_p_eq;
  /// The equilibrium a user checks by hand, over the whole model: the supports' reactions (at
  /// every prescribed node), the applied loads and the rigid surfaces' forces; they sum to
  /// zero (to the residual).
  struct Balance {
    Vec3 supports = Vec3::Zero(), loads = Vec3::Zero(), contact = Vec3::Zero();
    double force_scale = 0;  ///< Σ over the nodes of |F_int|
    /// |supports + loads + contact| over the largest of them and force_scale.
    double imbalance() const;
  };
  Balance balance;
};
StepValues step_values(const Model& model, const State& state, const RecoveredFields& fields);

}  // namespace hencky
