#pragma once
// A rigid surface type as an object that declares itself (STYLE.md; as a point law does,
// material/point_law.hpp, and MOOSE's validParams with registerMooseObject). A type declares
// - its name, the key under a contact's `surface:` that selects it (plane, sphere, ...);
// - its keys (SurfaceKey), each with its kind: the case reader (input/case_contact.cpp) reads
//   and checks them by kind, refuses unknown ones with the usual suggestion, and keeps the
//   values by key (SurfaceParameters, spec/case.hpp);
// - its geometry: `make` builds the RigidSurface (rigid_surface.hpp) from those values, in its
//   own frame at t = 0. The motion is the contact's, not the type's: a rigid translation
//   (contact[i].motion) that the contact code applies by moving the query points, the same for
//   every type (rigid_surface.hpp);
// - its description in summary.json (contact.<name>.surface, which scripts/render.py draws
//   from): `describe`, a list of (key, value) pairs that the writer turns into JSON;
// - its name in the log line ("a plane", "an STL body").
// A new type: its RigidSurface and its declaration in contact/, its declaration's function
// below, and one line in surface_types() (surface_type.cpp). docs/development.md, "Where to add".
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "contact/rigid_surface.hpp"
#include "spec/case.hpp"

namespace hencky {

/// A key of a surface type, under contact[i].surface.<type>.
struct SurfaceKey {
  enum class Kind {
    vector,       ///< [x, y, z]
    unit_vector,  ///< [x, y, z], not all zero; kept normalized
    positive,     ///< a number > 0
    file,         ///< a file name, relative to the case file's folder; the file must exist
  };
  std::string name;
  Kind kind = Kind::vector;
  /// What the value is, in the message when a required key is missing.
  std::string description;
  /// Its value in the type's sketch, "a sphere {center: [x, y, z], radius: r}".
  std::string example;
  /// An optional key's value when it is not given; none: the key is required.
  std::optional<SurfaceValue> fallback = std::nullopt;
  /// A file: what it is, in "STL file '...' not found".
  std::string file_kind = {};
};

/// A value of summary.json's surface description.
using SurfaceDescriptionValue = std::variant<double, Vec3, std::string>;
/// summary.json's contact.<name>.surface as (key, value) pairs.
using SurfaceDescription = std::vector<std::pair<std::string, SurfaceDescriptionValue>>;

/// {shape: <type>} then every declared key with its value (a path as its string): what
/// scripts/render.py reads for every type registered today.
SurfaceDescription describe_keys(const SurfaceParameters& p);

/// A surface type the case can ask for. `make` and `describe` get parameters the reader has
/// read and checked by this declaration's keys; `make` throws InputError for what only the
/// geometry can refuse (an STL file that bounds no solid).
struct SurfaceDeclaration {
  std::string name;  ///< its key under `surface:`, and summary.json's `shape`
  std::string noun;  ///< in the log line: "a plane", "an STL body"
  std::vector<SurfaceKey> keys;
  std::function<std::unique_ptr<RigidSurface>(const SurfaceParameters&)> make;
  std::function<SurfaceDescription(const SurfaceParameters&)> describe = describe_keys;
};

/// Every registered surface type, in the order messages list them.
const std::vector<SurfaceDeclaration>& surface_types();

/// The registered type of that name (InternalError when there is none: the reader checked it).
const SurfaceDeclaration& surface_type(const std::string& name);

/// The registered types' declarations, each beside its geometry.
SurfaceDeclaration plane_declaration();     // rigid_surface.cpp
SurfaceDeclaration sphere_declaration();    // rigid_surface.cpp
SurfaceDeclaration cylinder_declaration();  // rigid_surface.cpp
SurfaceDeclaration stl_mesh_declaration();  // stl_surface.cpp

}  // namespace hencky
