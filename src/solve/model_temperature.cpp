// Temperatures: a temperature file's rows bound to the nodes, the nodal temperature at a time,
// and the thermal strains' range checks.
#include "solve/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "core/invariant.hpp"

namespace hencky {

void Model::bind_temperature() {
  const auto& ts = case_->temperature;
  if (!ts.file) return;
  const TemperatureFile& tf = *ts.file;
  std::unordered_map<long, int> row_of_tag;
  for (std::size_t r = 0; r < tf.node_tags.size(); ++r) row_of_tag.emplace(tf.node_tags[r], r);
  temperature_.row.resize(mesh_.n_nodes());
  int n_missing = 0;
  long first_missing = 0;
  for (int n = 0; n < mesh_.n_nodes(); ++n) {
    auto it = row_of_tag.find(mesh_.node_tag[n]);
    if (it == row_of_tag.end()) {
      if (n_missing++ == 0) first_missing = mesh_.node_tag[n];
      continue;
    }
    temperature_.row[n] = it->second;
  }
  if (n_missing > 0)
    throw InputError(SourceLocation{tf.path.string(), 0, 0, "temperature.field.file"},
                     fmt::format("{} nodes of the mesh have no temperature in this file, e.g. "
                                 "Gmsh node {}",
                                 n_missing, first_missing));
}

bool Model::thermal_in_range(int mi, const ElasticConstants& k, double T) const {
  const double strain = k.thermal_strain(T) - temperature_.reference_strain[mi];
  return std::isfinite(strain) && std::isfinite(k.E / (1 - 2 * k.nu) * strain);
}

void Model::thermal_out_of_range(int cell, double T, double t) const {
  thermal_out_of_range(CellFacts{mesh_.cells.tag[cell], cell_material_[cell]}, T, t);
}

void Model::thermal_out_of_range(const CellFacts& cell, double T, double t) const {
  const int mi = cell.material;
  const ElasticConstants k = materials_[mi].at(T);
  const double strain = k.thermal_strain(T) - temperature_.reference_strain[mi];
  const auto& ts = case_->temperature;
  throw InputError(
      ts.field_where,
      fmt::format("the temperature {:g} at element {} (material '{}'{}) gives the thermal strain "
                  "alpha(T)*T - alpha(T_ref)*T_ref = {:g} (alpha = {:g}, T_ref = {:g}) and, fully "
                  "restrained, the stress E/(1 - 2nu) times that = {:g}: beyond the range of "
                  "floating point; check the temperatures' magnitude and units",
                  T, cell.tag, materials_[mi].spec->name,
                  std::isnan(t) ? std::string() : fmt::format(", t = {:g}", t), strain, k.alpha,
                  temperature_.reference, k.E / (1 - 2 * k.nu) * strain));
}

void Model::check_temperature_range() {
  // What can be known before the first step (so that `hencky check` finds it too); the step
  // loop checks every point's temperature at every step (PointPass::temperatures).
  const auto& ts = case_->temperature;
  auto& ref = temperature_.reference_strain;
  ref.clear();
  for (const auto& m : materials_) {
    ref.push_back(m.at(temperature_.reference).thermal_strain(temperature_.reference));
    if (!std::isfinite(ref.back()))
      throw InputError(ts.reference_where,
                       fmt::format("T_ref = {:g} gives material '{}' alpha(T_ref)*T_ref = {:g}: "
                                   "beyond the range of floating point; check its magnitude "
                                   "and units",
                                   temperature_.reference, m.spec->name, ref.back()));
  }
  if (!ts.given) return;
  // Per cell, the lowest and the highest temperature any of its nodes takes: a constant field
  // takes one value; a file, each node's range over its times.
  std::vector<double> lo, hi;
  if (ts.field && ts.field->is_constant()) {
    const double T = (*ts.field)(0, 0, 0, 0);
    lo.assign(mesh_.n_nodes(), T);
    hi.assign(mesh_.n_nodes(), T);
  } else if (ts.file) {
    const std::size_t n_times = ts.file->times.size();
    lo.resize(mesh_.n_nodes());
    hi.resize(mesh_.n_nodes());
    for (int n = 0; n < mesh_.n_nodes(); ++n) {
      const double* v = ts.file->values.data() + temperature_.row[n] * n_times;
      lo[n] = *std::min_element(v, v + n_times);
      hi[n] = *std::max_element(v, v + n_times);
    }
  } else {
    return;  // an expression: known at the steps only
  }
  for (int e = 0; e < mesh_.cells.size(); ++e)
    for (int n : mesh_.cells.nodes(e))
      for (double T : {lo[n], hi[n]})
        if (!thermal_in_range(cell_material_[e], material_of(e).at(T), T))
          thermal_out_of_range(e, T, NAN);
}

void Model::nodal_temperature(double t, std::vector<double>& T) const {
  const auto& ts = case_->temperature;
  T.resize(mesh_.n_nodes());
  if (ts.file) {
    for (int n = 0; n < mesh_.n_nodes(); ++n) T[n] = ts.file->at(temperature_.row[n], t);
  } else if (ts.field) {
    for (int n = 0; n < mesh_.n_nodes(); ++n) {
      const Vec3& x = mesh_.x[n];
      T[n] = ts.field->eval_checked(x.x(), x.y(), x.z(), t, "temperature");
    }
  } else {
    HENCKY_VERIFY(!ts.from_heat, "temperature from: heat is the heat analysis's (HeatSolver::at)");
    std::fill(T.begin(), T.end(), temperature_.reference);
  }
}

}  // namespace hencky
