#pragma once
// What the writing of a checkpoint (checkpoint.cpp) and its reading (checkpoint_restore.cpp)
// must agree on: the order of the integration points in the file, the widths and the order of
// the numbers of a point's tangent and of a contact point's state, and the fingerprints of the
// named lists. Internal to output/: the file's layout is checkpoint_file.hpp's.
#include <cstdint>
#include <string>
#include <vector>

#include "solve/analysis.hpp"

namespace hencky::checkpoint_records {

/// The names of a list's entries (regions, materials) and their fingerprints.
struct Named {
  std::vector<std::string> names;
  std::vector<std::int64_t> prints;
};
/// The case's materials and their fingerprints.
Named materials_of(const Case& c);

/// Where each cell's points start in the whole mesh's order (the order of a checkpoint); the
/// last entry is the whole model's count. On a part, for its own cells.
std::vector<long long> global_offsets(const Model& model);

/// f(p, g) for every point this rank holds: p its index in the rank's arrays, g in the whole
/// mesh's order.
template <class F>
void for_each_held_point(const Model& model, const std::vector<long long>& off, F&& f) {
  for (int e = 0; e < model.mesh().cells.size(); ++e) {
    if (!model.holds_points(e)) continue;
    const int n = model.point_offset(e + 1) - model.point_offset(e);
    for (int q = 0; q < n; ++q) f(model.point_offset(e) + q, off[e] + q);
  }
}

inline void put_voigt(double* out, const Voigt& v) {
  for (int c = 0; c < 6; ++c) out[c] = v[c];
}
inline Voigt get_voigt(const double* in) {
  Voigt v;
  for (int c = 0; c < 6; ++c) v[c] = in[c];
  return v;
}

/// A point's tangent: dev_scale, coef, then v (6).
constexpr int tangent_width = 8;
inline void put_tangent(double* out, const Tangent& t) {
  out[0] = t.dev_scale;
  out[1] = t.coef;
  put_voigt(out + 2, t.v);
}
inline Tangent get_tangent(const double* in) {
  Tangent t;
  t.dev_scale = in[0];
  t.coef = in[1];
  t.v = get_voigt(in + 2);
  return t;
}

/// A contact point's state: force 3, point 3, normal 3, kappa, gap (its two flags in a record
/// of their own).
constexpr int contact_width = 11;

}  // namespace hencky::checkpoint_records
