#pragma once
// What hencky takes from a Gmsh model, whichever way the model was obtained: parsed from a
// .msh file by hencky's own reader (msh_reader), or taken from the Gmsh library after it meshed
// a .geo or converted the element order (gmsh_reader). One conversion, to_mesh, turns it into
// the solver's Mesh, so both ways number nodes, cells, faces and regions alike.
#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "input/gmsh_reader.hpp"
#include "mesh/mesh.hpp"

namespace hencky {

/// One Gmsh element type: its number in the MSH format, node count, dimension and name.
struct GmshElementType {
  int type;
  int nodes;
  int dim;
  const char* name;
};

/// The element type with this MSH number, or nullptr when hencky does not know it (MSH types
/// with a fixed node count, as Gmsh 4.8 defines them).
const GmshElementType* gmsh_element_type(int type);

/// "Tetrahedron 10 (Gmsh type 11)", or "Gmsh element type N" for an unknown type.
std::string gmsh_type_name(int type);

struct MshData {
  struct Entity {
    int dim = 0;
    int tag = 0;
    std::vector<int> physicals;  ///< physical group tags, each once
  };
  /// The elements of one type on one entity, in the order the file or Gmsh holds them.
  struct Block {
    int dim = 0;
    int entity = 0;
    int type = 0;
    std::vector<std::size_t> tags;
    std::vector<std::size_t> nodes;  ///< tags.size() * nodes-per-element node tags
  };
  std::vector<std::size_t> node_tags;
  std::vector<double> coords;  ///< x, y, z of node_tags[i] at 3i .. 3i+2
  std::vector<Entity> entities;
  std::vector<Block> blocks;
  std::map<std::pair<int, int>, std::string> physical_names;  ///< (dim, tag) -> name
  /// A partitioned file: its count of partitions, and for one file of a split mesh read as a
  /// piece (parse_msh's `piece`), the partition it holds (0 otherwise).
  int partitions = 0, piece = 0;
};

/// The solver's mesh from a Gmsh model, with the rules of read_gmsh (gmsh_reader.hpp). Entities
/// are taken in order of (dimension, tag) and their elements type by type, as the Gmsh API
/// returns them. `file` names the source in messages. Throws InputError.
Mesh to_mesh(const MshData& data, const MeshReadOptions& options, const std::string& file);

}  // namespace hencky
