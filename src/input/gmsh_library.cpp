#include "input/gmsh_library.hpp"

#include <dlfcn.h>

#include <mutex>
#include <stdexcept>

// The C API's declarations, for the types of its functions only: nothing is linked against.
extern "C" {
#include <gmshc.h>
}

#ifndef HENCKY_GMSH_LIBRARY
#define HENCKY_GMSH_LIBRARY "libgmsh.so.4.8"
#endif

namespace hencky::gmsh_library {
namespace {

struct Api {
  decltype(&::gmshFree) free = nullptr;
  decltype(&::gmshInitialize) initialize = nullptr;
  decltype(&::gmshFinalize) finalize = nullptr;
  decltype(&::gmshOptionSetNumber) set_number = nullptr;
  decltype(&::gmshLoggerStart) logger_start = nullptr;
  decltype(&::gmshLoggerStop) logger_stop = nullptr;
  decltype(&::gmshLoggerGet) logger_get = nullptr;
  decltype(&::gmshLoggerGetLastError) last_error = nullptr;
  decltype(&::gmshOpen) open = nullptr;
  decltype(&::gmshModelMeshGenerate) generate = nullptr;
  decltype(&::gmshModelMeshSetOrder) set_order = nullptr;
  decltype(&::gmshModelMeshGetNodes) get_nodes = nullptr;
  decltype(&::gmshModelGetEntities) get_entities = nullptr;
  decltype(&::gmshModelGetPhysicalGroupsForEntity) groups_for_entity = nullptr;
  decltype(&::gmshModelGetParent) get_parent = nullptr;
  decltype(&::gmshModelMeshGetElements) get_elements = nullptr;
  decltype(&::gmshModelGetPhysicalGroups) physical_groups = nullptr;
  decltype(&::gmshModelGetPhysicalName) physical_name = nullptr;
};

Api api;

template <class F>
void bind(void* library, F& f, const char* name) {
  f = reinterpret_cast<F>(dlsym(library, name));
  if (!f)
    throw std::runtime_error(std::string("the Gmsh library " HENCKY_GMSH_LIBRARY " lacks ") +
                             name + " (another Gmsh version than 4.8?)");
}

void check(int ierr) {
  if (ierr) throw GmshError{};
}

/// Copies an array Gmsh allocated and frees it.
template <class T>
std::vector<T> take(T* p, std::size_t n) {
  std::vector<T> v(p, p + n);
  api.free(p);
  return v;
}

std::string take_string(char* p) {
  std::string s = p ? p : "";
  api.free(p);
  return s;
}

std::vector<std::pair<int, int>> pairs(int* p, std::size_t n) {
  std::vector<std::pair<int, int>> v;
  for (std::size_t k = 0; k + 1 < n; k += 2) v.emplace_back(p[k], p[k + 1]);
  api.free(p);
  return v;
}

}  // namespace

void load() {
  static std::once_flag once;
  static std::string failure;
  std::call_once(once, [] {
    void* library = dlopen(HENCKY_GMSH_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (!library) {
      const char* e = dlerror();
      failure = std::string("the Gmsh library could not be loaded (") + (e ? e : "dlopen failed") +
                "); it is the Debian package libgmsh4.8, installed by scripts/setup.sh";
      return;
    }
    try {
      bind(library, api.free, "gmshFree");
      bind(library, api.initialize, "gmshInitialize");
      bind(library, api.finalize, "gmshFinalize");
      bind(library, api.set_number, "gmshOptionSetNumber");
      bind(library, api.logger_start, "gmshLoggerStart");
      bind(library, api.logger_stop, "gmshLoggerStop");
      bind(library, api.logger_get, "gmshLoggerGet");
      bind(library, api.last_error, "gmshLoggerGetLastError");
      bind(library, api.open, "gmshOpen");
      bind(library, api.generate, "gmshModelMeshGenerate");
      bind(library, api.set_order, "gmshModelMeshSetOrder");
      bind(library, api.get_nodes, "gmshModelMeshGetNodes");
      bind(library, api.get_entities, "gmshModelGetEntities");
      bind(library, api.groups_for_entity, "gmshModelGetPhysicalGroupsForEntity");
      bind(library, api.get_parent, "gmshModelGetParent");
      bind(library, api.get_elements, "gmshModelMeshGetElements");
      bind(library, api.physical_groups, "gmshModelGetPhysicalGroups");
      bind(library, api.physical_name, "gmshModelGetPhysicalName");
    } catch (const std::exception& e) {
      failure = e.what();
      api = Api{};
    }
  });
  if (!failure.empty()) throw std::runtime_error(failure);
}

void initialize() {
  int ierr = 0;
  api.initialize(0, nullptr, 0, &ierr);
  check(ierr);
}

void finalize() {
  int ierr = 0;
  api.finalize(&ierr);
  check(ierr);
}

void set_number(const char* option, double value) {
  int ierr = 0;
  api.set_number(option, value, &ierr);
  check(ierr);
}

void logger_start() {
  int ierr = 0;
  api.logger_start(&ierr);
  check(ierr);
}

void logger_stop() {
  int ierr = 0;
  api.logger_stop(&ierr);
  check(ierr);
}

std::vector<std::string> logger_get() {
  int ierr = 0;
  char** lines = nullptr;
  std::size_t n = 0;
  api.logger_get(&lines, &n, &ierr);
  check(ierr);
  std::vector<std::string> out;
  for (std::size_t k = 0; k < n; ++k) out.push_back(take_string(lines[k]));
  api.free(lines);
  return out;
}

std::string last_error() {
  int ierr = 0;
  char* e = nullptr;
  api.last_error(&e, &ierr);
  return ierr ? std::string() : take_string(e);
}

void open(const std::string& file) {
  int ierr = 0;
  api.open(file.c_str(), &ierr);
  check(ierr);
}

void generate(int dim) {
  int ierr = 0;
  api.generate(dim, &ierr);
  check(ierr);
}

void set_order(int order) {
  int ierr = 0;
  api.set_order(order, &ierr);
  check(ierr);
}

void get_nodes(std::vector<std::size_t>& tags, std::vector<double>& coords) {
  int ierr = 0;
  std::size_t *t = nullptr, nt = 0, nx = 0, np = 0;
  double *x = nullptr, *param = nullptr;
  api.get_nodes(&t, &nt, &x, &nx, &param, &np, -1, -1, 0, 0, &ierr);
  check(ierr);
  tags = take(t, nt);
  coords = take(x, nx);
  api.free(param);
}

std::vector<std::pair<int, int>> get_entities(int dim) {
  int ierr = 0;
  int* p = nullptr;
  std::size_t n = 0;
  api.get_entities(&p, &n, dim, &ierr);
  check(ierr);
  return pairs(p, n);
}

std::vector<int> physical_groups_for_entity(int dim, int tag) {
  int ierr = 0;
  int* p = nullptr;
  std::size_t n = 0;
  api.groups_for_entity(dim, tag, &p, &n, &ierr);
  check(ierr);
  return take(p, n);
}

std::pair<int, int> parent(int dim, int tag) {
  int ierr = 0, parent_dim = -1, parent_tag = -1;
  api.get_parent(dim, tag, &parent_dim, &parent_tag, &ierr);
  check(ierr);
  return {parent_dim, parent_tag};
}

void get_elements(int dim, int tag, std::vector<int>& types,
                  std::vector<std::vector<std::size_t>>& element_tags,
                  std::vector<std::vector<std::size_t>>& node_tags) {
  int ierr = 0;
  int* t = nullptr;
  std::size_t nt = 0;
  std::size_t **et = nullptr, *et_n = nullptr, et_nn = 0;
  std::size_t **nd = nullptr, *nd_n = nullptr, nd_nn = 0;
  api.get_elements(&t, &nt, &et, &et_n, &et_nn, &nd, &nd_n, &nd_nn, dim, tag, &ierr);
  check(ierr);
  types = take(t, nt);
  element_tags.clear();
  node_tags.clear();
  for (std::size_t k = 0; k < et_nn; ++k) element_tags.push_back(take(et[k], et_n[k]));
  for (std::size_t k = 0; k < nd_nn; ++k) node_tags.push_back(take(nd[k], nd_n[k]));
  api.free(et);
  api.free(et_n);
  api.free(nd);
  api.free(nd_n);
}

std::vector<std::pair<int, int>> physical_groups(int dim) {
  int ierr = 0;
  int* p = nullptr;
  std::size_t n = 0;
  api.physical_groups(&p, &n, dim, &ierr);
  check(ierr);
  return pairs(p, n);
}

std::string physical_name(int dim, int tag) {
  int ierr = 0;
  char* name = nullptr;
  api.physical_name(dim, tag, &name, &ierr);
  check(ierr);
  return take_string(name);
}

}  // namespace hencky::gmsh_library
