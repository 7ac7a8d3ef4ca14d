#pragma once
// The point law of a plastic material as an interface (STYLE.md, "objects that declare
// themselves"; as MOOSE's validParams with registerMooseObject, MFEM's HyperelasticModel).
// A law declares
// - its keys under `plasticity:` (LawKey): the case reader reads them, refuses unknown ones
//   with the usual suggestion, and the law is made from what was read (LawDeclaration::make);
// - its internal variables besides σ, ε^p and ε̃^p (LawVariable): the state keeps them per
//   point (State::internal), checkpoints and restarts carry them, the outputs name them;
// - its point update for a mechanical strain increment at the step's temperature, with its
//   consistent tangent (newton), and whether the report's five schemes can run it: they need
//   the report's structure, one curve Φ(ε̃, T) along Z, which the isotropic von Mises law has.
// Von Mises with the isotropic curve is the first law; Prager's linear kinematic hardening the
// second (material/kinematic.hpp). A new law: its class and its declaration in material/, and
// one line in point_laws() (point_law.cpp). docs/development.md, "Where to add".
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "material/hardening.hpp"
#include "material/plastic_point.hpp"
#include "spec/case.hpp"

namespace hencky {

/// An internal variable of a law at each point.
struct LawVariable {
  std::string name;  ///< its output name (VTU field, probe column, summary.json key)
  int size = 1;      ///< 1: a scalar; 6: a symmetric tensor, stress-like Voigt order
};

/// A key a law reads under `plasticity:`: a list of groups of named fields, each field a number
/// or a temperature table (`kinematic: [{C: 2e9, gamma: 0}]`).
struct LawKey {
  std::string name;
  std::vector<std::string> fields;  ///< every field of a group is required
  std::string unit;                 ///< of the fields, for messages and docs ("Pa, 1")
};

class PointLaw {
 public:
  virtual ~PointLaw() = default;
  /// The internal variables, in the order of the point's state (State::internal).
  virtual std::span<const LawVariable> variables() const { return {}; }
  /// Numbers of state per point: the sum of the variables' sizes.
  int state_size() const;
  /// The report's five schemes can run it: one isotropic curve Φ(ε̃, T) along Z (2.9)-(2.46).
  virtual bool runs_report_schemes() const { return false; }
  /// newton's point update from the state at t (σ(t) = `sigma0`, the law's `state0`) for the
  /// mechanical strain increment `d_mech` = Δε − Δε^th at the step's temperature
  /// (`curve.temperature`, E, ν of `k`): the stress, the plastic increment z·Δλ and the
  /// consistent tangent; the law's state at t+Δt into `state1`. A pure function.
  virtual ReturnMapping update(const ElasticConstants& k, const StepCurve& curve,
                               const Voigt& sigma0, const Voigt& d_mech,
                               std::span<const double> state0, std::span<double> state1) const = 0;
  /// The stress whose von Mises value the yield stress bounds: σ itself, or σ − α of a law with
  /// a back stress α in its state (the admissibility check, PointPass::largest_excess).
  virtual Voigt relative_stress(const Voigt& sigma, std::span<const double> state) const {
    (void)state;
    return sigma;
  }
};

/// A law the case can ask for: its name (for messages), the keys that select it, and how it is
/// made from what the reader found (`spec` is the material's whole plasticity entry). `make`
/// throws InputError naming the key for values the law cannot take.
struct LawDeclaration {
  std::string name;
  std::vector<LawKey> keys;
  std::function<std::shared_ptr<const PointLaw>(const PlasticitySpec& spec)> make;
};

/// Every registered law but the isotropic one, which is the default (no key selects it).
const std::vector<LawDeclaration>& point_laws();

/// The law of a plastic material: the isotropic von Mises law, or the registered law that its
/// keys selected (spec.law.law).
std::shared_ptr<const PointLaw> make_point_law(const PlasticitySpec& spec);

/// Von Mises plasticity with the isotropic curve: the radial return (plastic_point.hpp).
class IsotropicLaw final : public PointLaw {
 public:
  bool runs_report_schemes() const override { return true; }
  ReturnMapping update(const ElasticConstants& k, const StepCurve& curve, const Voigt& sigma0,
                       const Voigt& d_mech, std::span<const double>,
                       std::span<double>) const override {
    return radial_return(k, curve, sigma0, d_mech);
  }
};

}  // namespace hencky
