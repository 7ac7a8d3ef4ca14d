#include "material/point_law.hpp"

#include "material/kinematic.hpp"

namespace hencky {

int PointLaw::state_size() const {
  int n = 0;
  for (const LawVariable& v : variables()) n += v.size;
  return n;
}

const std::vector<LawDeclaration>& point_laws() {
  // The registry: one line per law.
  static const std::vector<LawDeclaration> laws = {
      kinematic_law_declaration(),
  };
  return laws;
}

std::shared_ptr<const PointLaw> make_point_law(const PlasticitySpec& spec) {
  for (const LawDeclaration& d : point_laws())
    if (d.name == spec.law.law) return d.make(spec);
  return std::make_shared<IsotropicLaw>();
}

}  // namespace hencky
