#pragma once
// The Gmsh library, loaded when a run first needs it (a .geo to mesh, an element order to
// convert) instead of at every process start. Linked, libgmsh and its ~70 shared libraries of
// its own took ~0.1 s of dynamic linking before main(), in every run, also of cases with a .msh
// file that hencky reads itself (docs/performance.md, "Start-up"). Loaded with dlopen, through
// its C API (gmshc.h), whose functions report errors through an `ierr` argument instead of C++
// exceptions.
#include <string>
#include <utility>
#include <vector>

namespace hencky::gmsh_library {

/// Loads the library (once per process). Throws std::runtime_error naming the library and the
/// Debian package when it cannot be loaded.
void load();

// The calls hencky makes; each throws GmshError when Gmsh reports an error, whose text is
// last_error() (Gmsh's logger keeps it; the reader reads it there, whatever stopped Gmsh).
struct GmshError {};
void initialize();
void finalize();
void set_number(const char* option, double value);
void logger_start();
void logger_stop();
std::vector<std::string> logger_get();
std::string last_error();
void open(const std::string& file);
void generate(int dim);
void set_order(int order);
void get_nodes(std::vector<std::size_t>& tags, std::vector<double>& coords);
std::vector<std::pair<int, int>> get_entities(int dim);
std::vector<int> physical_groups_for_entity(int dim, int tag);
/// The entity a partitioned entity is a piece of, (-1, -1) for a model entity.
std::pair<int, int> parent(int dim, int tag);
/// The element blocks of an entity (dim, tag; -1 for all): per element type its element tags
/// and node tags.
void get_elements(int dim, int tag, std::vector<int>& types,
                  std::vector<std::vector<std::size_t>>& element_tags,
                  std::vector<std::vector<std::size_t>>& node_tags);
std::vector<std::pair<int, int>> physical_groups(int dim);
std::string physical_name(int dim, int tag);

}  // namespace hencky::gmsh_library
