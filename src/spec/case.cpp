#include "spec/case.hpp"

#include <algorithm>

#include "core/invariant.hpp"

namespace hencky {

double PropertyTable::operator()(double T, bool* outside) const {
  if (outside) *outside = false;
  if (value.size() == 1 || temperature.size() != value.size()) return value.at(0);
  if (T < temperature.front() || T > temperature.back()) {
    if (outside) *outside = true;
    return T < temperature.front() ? value.front() : value.back();
  }
  const auto it = std::upper_bound(temperature.begin(), temperature.end(), T);
  if (it == temperature.end()) return value.back();  // T == last temperature
  const std::size_t i = static_cast<std::size_t>(it - temperature.begin());  // >= 1
  const double s = (T - temperature[i - 1]) / (temperature[i] - temperature[i - 1]);
  return value[i - 1] + s * (value[i] - value[i - 1]);
}

double PropertyTable::slope(double T) const {
  if (value.size() < 2 || temperature.size() != value.size()) return 0.0;
  if (T < temperature.front() || T >= temperature.back()) return 0.0;
  const auto it = std::upper_bound(temperature.begin(), temperature.end(), T);
  const std::size_t i = static_cast<std::size_t>(it - temperature.begin());  // >= 1
  return (value[i] - value[i - 1]) / (temperature[i] - temperature[i - 1]);
}

double TemperatureFile::at(std::size_t row, double t) const {
  const std::size_t n = times.size();
  const double* v = values.data() + row * n;
  if (n == 1 || t <= times.front()) return v[0];
  if (t >= times.back()) return v[n - 1];
  const auto it = std::upper_bound(times.begin(), times.end(), t);
  const std::size_t j = static_cast<std::size_t>(it - times.begin());  // 1 <= j < n
  const double s = (t - times[j - 1]) / (times[j] - times[j - 1]);
  return v[j - 1] + s * (v[j] - v[j - 1]);
}

const char* to_string(BoundaryKind kind) {
  switch (kind) {
    case BoundaryKind::displacement:
      return "displacement";
    case BoundaryKind::pressure:
      return "pressure";
    case BoundaryKind::traction:
      return "traction";
    case BoundaryKind::force:
      return "force";
    case BoundaryKind::nodal_force:
      return "nodal_force";
  }
  return "?";
}

namespace {
template <class T>
const T& surface_value(const SurfaceParameters& p, const std::string& key) {
  const auto it = p.values.find(key);
  HENCKY_VERIFY(it != p.values.end() && std::holds_alternative<T>(it->second.value),
                "surface type '" + p.type + "' declares no key '" + key + "' of that kind");
  return std::get<T>(it->second.value);
}
}  // namespace

double SurfaceParameters::number(const std::string& key) const {
  return surface_value<double>(*this, key);
}

const Vec3& SurfaceParameters::vector(const std::string& key) const {
  return surface_value<Vec3>(*this, key);
}

const std::filesystem::path& SurfaceParameters::path(const std::string& key) const {
  return surface_value<std::filesystem::path>(*this, key);
}

}  // namespace hencky
