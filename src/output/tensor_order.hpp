#pragma once
// The order and the names of the components the outputs write (history.csv, summary.json and
// the fields files, results.hpp), shared by their writers. Internal to output/.
#include <array>

#include "core/types.hpp"

namespace hencky::tensor_order {

// Voigt {11,22,33,23,31,12} -> ParaView's XX YY ZZ XY YZ XZ.
constexpr std::array<int, 6> paraview_order{0, 1, 2, 5, 3, 4};
constexpr std::array<const char*, 6> paraview_names{"xx", "yy", "zz", "xy", "yz", "xz"};
constexpr std::array<const char*, 3> axes{"x", "y", "z"};
// The strains of issue 17, as tensors (ε_xy = γ_xy / 2) in ParaView's order like the stress.
// The probes' columns: ε = ε^e + ε^p + ε^th, all four.
constexpr std::array<const char*, 4> strain_fields{"strain", "elastic_strain", "plastic_strain",
                                                   "thermal_strain"};
/// Component c, in ParaView's order, of a strain with engineering shears, as a tensor.
inline double tensor_component(const Voigt& engineering, int c) {
  return engineering[paraview_order[c]] * (c < 3 ? 1.0 : 0.5);
}

}  // namespace hencky::tensor_order
