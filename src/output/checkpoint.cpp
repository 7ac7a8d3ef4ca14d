// Checkpoints: the record of a run's memory, its fingerprints, and the files of an output
// directory (checkpoint.hpp).
#include "output/checkpoint.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>

#include "core/error.hpp"
#include "fem/reference_element.hpp"
#include "hencky/version.hpp"
#include "parallel/mpi.hpp"

namespace hencky {
namespace fs = std::filesystem;
namespace {

// ---- Fingerprints ---------------------------------------------------------------------------

/// FNV-1a, 64 bits: a fingerprint to tell "the same" from "changed", not a defence against a
/// forged file (the checksum of the container catches damage).
class Hash {
 public:
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h_ = (h_ ^ b[i]) * 1099511628211ull;
  }
  template <class T>
  void add(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  template <class T>
  void add(const std::vector<T>& v) {
    add(v.size());
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
  void add(const std::string& s) {
    add(s.size());
    bytes(s.data(), s.size());
  }
  void add(const PropertyTable& t) {
    add(t.temperature);
    add(t.value);
  }
  std::int64_t value() const { return static_cast<std::int64_t>(h_); }

 private:
  std::uint64_t h_ = 14695981039346656037ull;
};

std::int64_t mesh_fingerprint(const Mesh& mesh) {
  Hash h;
  h.add(mesh.n_nodes());
  for (const Vec3& x : mesh.x) h.bytes(x.data(), 3 * sizeof(double));
  h.add(mesh.cells.type);
  h.add(mesh.cells.offset);
  h.add(mesh.cells.conn);
  return h.value();
}

std::int64_t region_fingerprint(const Region& r) {
  Hash h;
  h.add(r.dim);
  h.add(r.cells);
  h.add(r.nodes);
  return h.value();
}

std::int64_t material_fingerprint(const MaterialSpec& m) {
  Hash h;
  h.add(m.regions.size());
  for (const auto& r : m.regions) h.add(r);
  for (const PropertyTable* t :
       {&m.E, &m.nu, &m.alpha, &m.conductivity, &m.density, &m.specific_heat})
    h.add(*t);
  h.add(m.plasticity.has_value());
  if (m.plasticity) {
    const CurveSpec& c = m.plasticity->curve;
    h.add(c.kind);
    h.add(c.form);
    h.add(c.tables.size());
    for (const auto& t : c.tables) {
      h.add(t.temperature);
      h.add(t.strain);
      h.add(t.stress);
    }
    h.add(c.yield);
    h.add(c.hardening);
    h.add(c.ro_E);
    h.add(c.ro_alpha);
    h.add(c.ro_n);
    h.add(m.plasticity->unloading);
  }
  return h.value();
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : "\n") + n;
  return s;
}
std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  if (s.empty()) return out;
  std::size_t at = 0;
  for (;;) {
    const std::size_t nl = s.find('\n', at);
    out.push_back(s.substr(at, nl == std::string::npos ? std::string::npos : nl - at));
    if (nl == std::string::npos) return out;
    at = nl + 1;
  }
}

struct Named {
  std::vector<std::string> names;
  std::vector<std::int64_t> prints;
};
/// The names of `list`'s entries and their fingerprints.
template <class List, class Print>
Named named(const List& list, Print print) {
  Named n;
  for (const auto& x : list) {
    n.names.push_back(x.name);
    n.prints.push_back(print(x));
  }
  return n;
}
Named regions_of(const Mesh& mesh) {
  return named(mesh.regions, region_fingerprint);
}
Named materials_of(const Case& c) {
  return named(c.materials, material_fingerprint);
}

void put_named(CheckpointFile& f, const std::string& key, const Named& n) {
  f.put(key + ".names", join(n.names));
  f.put(key + ".fingerprints", std::span<const std::int64_t>(n.prints));
}

/// The position of the k-th (from 0) entry `name` of `list`, or list.size().
std::size_t nth(const std::vector<std::string>& list, const std::string& name, std::size_t k) {
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list[i] == name && k-- == 0) return i;
  return list.size();
}

/// What differs between the checkpoint's `key` list and the model's ("" when nothing). A name
/// may be there more than once (an Abaqus deck's NSET and ELSET of one name): the k-th of a
/// name is compared with the k-th.
std::string named_change(const CheckpointFile& f, const std::string& key, const Named& now,
                         const char* what) {
  const auto names = split(f.text(key + ".names"));
  const auto& prints = f.i64(key + ".fingerprints", static_cast<long long>(names.size()));
  const auto before = [](const std::vector<std::string>& list, std::size_t i) {
    return static_cast<std::size_t>(std::count(list.begin(), list.begin() + i, list[i]));
  };
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::size_t j = nth(now.names, names[i], before(names, i));
    if (j == now.names.size())
      return fmt::format("{} '{}' of the checkpoint's run is not in the case", what, names[i]);
    if (now.prints[j] != prints[i])
      return fmt::format("{} '{}' is not the one the checkpoint was computed with", what, names[i]);
  }
  for (std::size_t i = 0; i < now.names.size(); ++i)
    if (nth(names, now.names[i], before(now.names, i)) == names.size())
      return fmt::format("{} '{}' is new: the checkpoint's run had none of that name", what,
                         now.names[i]);
  return "";
}

// ---- Point data ---------------------------------------------------------------------------

/// Where each cell's points start in the whole mesh's order (the order of a checkpoint); the
/// last entry is the whole model's count. On a part, for its own cells.
std::vector<long long> global_offsets(const Model& model) {
  const auto& cells = model.mesh().cells;
  std::vector<long long> off(cells.size() + 1, 0);
  if (model.part()) {
    for (int e = 0; e < cells.size(); ++e) off[e] = model.whole_point_offset(e);
    off.back() = model.total_points();
    return off;
  }
  for (int e = 0; e < cells.size(); ++e)
    off[e + 1] = off[e] + reference_table(cells.type[e]).n_points;
  return off;
}

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

/// Every rank's `mine`, on root in rank order (empty elsewhere). Collective.
std::vector<std::vector<double>> gather_doubles(const std::vector<double>& mine) {
  const std::vector<std::string> all = par::gather_strings(
      std::string(reinterpret_cast<const char*>(mine.data()), mine.size() * sizeof(double)));
  std::vector<std::vector<double>> out;
  for (const std::string& bytes : all) {
    std::vector<double>& v = out.emplace_back(bytes.size() / sizeof(double));
    if (!v.empty()) std::memcpy(v.data(), bytes.data(), v.size() * sizeof(double));
  }
  return out;
}

/// Every rank's runs of values placed on root into an array of `total` values: this rank's
/// run i is `length[i]` values, taken in turn from `values`, that go to `start[i]` onwards.
/// Empty except on root. Collective.
std::vector<double> gather_runs(const std::vector<long long>& start, const std::vector<int>& length,
                                const std::vector<double>& values, std::size_t total) {
  std::vector<double> heads;  // (start, length) per run; exact as doubles below 2^53
  heads.reserve(2 * start.size());
  for (std::size_t i = 0; i < start.size(); ++i) {
    heads.push_back(static_cast<double>(start[i]));
    heads.push_back(length[i]);
  }
  const auto all_heads = gather_doubles(heads);
  const auto all_values = gather_doubles(values);
  std::vector<double> out;
  if (!par::root()) return out;
  out.assign(total, 0.0);
  for (std::size_t r = 0; r < all_heads.size(); ++r) {
    std::size_t at = 0;
    for (std::size_t i = 0; i < all_heads[r].size(); i += 2) {
      const auto n = static_cast<std::size_t>(all_heads[r][i + 1]);
      std::copy_n(all_values[r].begin() + at, n,
                  out.begin() + static_cast<std::ptrdiff_t>(all_heads[r][i]));
      at += n;
    }
  }
  return out;
}

/// A nodal array of `width` values a node, in the whole mesh's order: the model's own, or on a
/// distributed mesh each owner's values, written into the file by their owner (put_runs).
void put_nodal(CheckpointFile& f, const std::string& key, const Model& model,
               std::span<const double> v, int width) {
  const MeshPart* part = model.part();
  if (!part) return f.put(key, v);
  std::vector<long long> start(part->owned_nodes);
  for (int i = 0; i < part->owned_nodes; ++i) start[i] = width * part->global_node[i];
  f.put_runs(key, static_cast<std::uint64_t>(width) * model.global_nodes(), std::move(start),
             std::vector<int>(part->owned_nodes, width),
             {v.begin(), v.begin() + static_cast<std::ptrdiff_t>(width) * part->owned_nodes});
}

/// A per-point quantity of `width` numbers in the whole mesh's order: on a distributed mesh
/// each part's cells' points, a run at each cell's whole-mesh place (put_runs); else the points
/// this rank holds, summed on root (collective).
void put_points(CheckpointFile& f, const std::string& key, const Model& model,
                const std::vector<long long>& off, int width,
                const std::function<void(int, double*)>& get) {
  const auto total = static_cast<std::size_t>(off.back()) * width;
  if (model.part()) {
    std::vector<long long> start;
    std::vector<int> length;
    std::vector<double> values;
    for (int e = 0; e < model.mesh().cells.size(); ++e) {
      const int n = model.point_offset(e + 1) - model.point_offset(e);
      start.push_back(off[e] * width);
      length.push_back(n * width);
      values.resize(values.size() + static_cast<std::size_t>(n) * width);
      for (int q = 0; q < n; ++q)
        get(model.point_offset(e) + q, &values[values.size() - (n - q) * width]);
    }
    return f.put_runs(key, total, std::move(start), std::move(length), std::move(values));
  }
  std::vector<double> g(total, 0.0);
  for_each_held_point(model, off, [&](int p, long long i) { get(p, &g[i * width]); });
  par::sum_to_root(g);
  f.put(key, std::span<const double>(g));
}

/// The other way: this rank's points from the file's record `key` of `width` numbers a point,
/// in the whole mesh's order (on a part, only its cells' runs of it are read).
void scatter(const CheckpointFile& f, const std::string& key, const Model& model,
             const std::vector<long long>& off, int width,
             const std::function<void(int, const double*)>& set) {
  const long long total = off.back() * width;
  if (!model.part()) {
    const std::vector<double>& g = f.f64(key, total);
    for_each_held_point(model, off, [&](int p, long long i) { set(p, &g[i * width]); });
    return;
  }
  std::vector<long long> start;
  std::vector<int> length;
  for (int e = 0; e < model.mesh().cells.size(); ++e) {
    start.push_back(off[e] * width);
    length.push_back((model.point_offset(e + 1) - model.point_offset(e)) * width);
  }
  const std::vector<double> mine = f.f64_runs(key, total, start, length);
  for (int p = 0; p < model.n_points(); ++p) set(p, &mine[static_cast<std::size_t>(p) * width]);
}

void put_voigt(double* out, const Voigt& v) {
  for (int c = 0; c < 6; ++c) out[c] = v[c];
}
Voigt get_voigt(const double* in) {
  Voigt v;
  for (int c = 0; c < 6; ++c) v[c] = in[c];
  return v;
}

constexpr int tangent_width = 8;
void put_tangent(double* out, const Tangent& t) {
  out[0] = t.dev_scale;
  out[1] = t.coef;
  put_voigt(out + 2, t.v);
}
Tangent get_tangent(const double* in) {
  Tangent t;
  t.dev_scale = in[0];
  t.coef = in[1];
  t.v = get_voigt(in + 2);
  return t;
}

// ---- Contact ---------------------------------------------------------------------------------

constexpr int contact_width = 11;  // force 3, point 3, normal 3, kappa, gap

/// The states of every surface's points, in the whole model's order: on a distributed mesh each
/// point from its node's owner, gathered on root. Collective then.
void put_contact(CheckpointFile& f, const std::string& key,
                 const std::vector<std::vector<ContactNode>>& contact, const Model& model) {
  f.put(key + ".bodies", static_cast<std::int64_t>(contact.size()));
  constexpr int w = contact_width + 1;  // and the flags
  const auto pack = [](const ContactNode& n, std::vector<double>& out) {
    for (const Vec3* x : {&n.force, &n.point, &n.normal})
      out.insert(out.end(), x->data(), x->data() + 3);
    out.push_back(n.kappa);
    out.push_back(n.gap);
    out.push_back(n.contact | (n.separation << 1));
  };
  for (std::size_t b = 0; b < contact.size(); ++b) {
    std::vector<double> all;
    if (!model.part()) {
      for (const ContactNode& n : contact[b]) pack(n, all);
    } else {
      const ContactBody& body = model.contacts()[b];
      const Partition& part = model.partition();
      std::vector<long long> start;
      std::vector<double> mine;
      for (std::size_t i = 0; i < contact[b].size(); ++i)
        if (part.node_owner[body.points[i].node] == part.rank) {
          start.push_back(static_cast<long long>(w) * body.whole_index[i]);
          pack(contact[b][i], mine);
        }
      all = gather_runs(start, std::vector<int>(start.size(), w), mine,
                        static_cast<std::size_t>(w) * body.whole_points);
    }
    std::vector<double> v;
    std::vector<std::uint8_t> flags;
    for (std::size_t j = 0; j + w <= all.size(); j += w) {
      v.insert(v.end(), all.begin() + j, all.begin() + j + contact_width);
      flags.push_back(static_cast<std::uint8_t>(all[j + contact_width]));
    }
    f.put(fmt::format("{}.{}.values", key, b), std::span<const double>(v));
    f.put(fmt::format("{}.{}.flags", key, b), std::span<const std::uint8_t>(flags));
  }
}

std::vector<std::vector<ContactNode>> get_contact(const CheckpointFile& f, const std::string& key,
                                                  const Model& model) {
  std::vector<std::vector<ContactNode>> contact;
  const auto& bodies = model.contacts();
  const auto n_bodies = f.integer(key + ".bodies");
  if (n_bodies == 0) return contact;  // no assembly kept
  if (n_bodies != static_cast<std::int64_t>(bodies.size()))
    throw InputError(SourceLocation{f.label(), 0, 0, "contact"},
                     fmt::format("the case has {} contact surfaces, the checkpoint's run had {}",
                                 bodies.size(), n_bodies));
  contact.resize(bodies.size());
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    // The file holds the whole model's points; a distributed mesh's part takes its own.
    const ContactBody& body = bodies[b];
    const long long n = static_cast<long long>(body.points.size());
    const long long stored = model.part() ? body.whole_points : n;
    const auto& v = f.f64(fmt::format("{}.{}.values", key, b), stored * contact_width);
    const auto& flags = f.u8(fmt::format("{}.{}.flags", key, b), stored);
    contact[b].resize(n);
    for (long long k = 0; k < n; ++k) {
      const long long i = model.part() ? body.whole_index[k] : k;
      ContactNode& c = contact[b][k];
      const double* x = &v[i * contact_width];
      c.force = Vec3(x[0], x[1], x[2]);
      c.point = Vec3(x[3], x[4], x[5]);
      c.normal = Vec3(x[6], x[7], x[8]);
      c.kappa = x[9];
      c.gap = x[10];
      c.contact = flags[i] & 1;
      c.separation = (flags[i] >> 1) & 1;
    }
  }
  return contact;
}

[[noreturn]] void changed(const CheckpointFile& f, const std::string& key,
                          const std::string& what) {
  throw InputError(SourceLocation{f.label(), 0, 0, key},
                   what +
                       ": a restart continues the same model (mesh, regions, materials); only "
                       "what comes after the restart time may change");
}

// ---- Files -----------------------------------------------------------------------------------

/// A file written whole and flushed at `tmp` becomes `path` (removed when it cannot).
void rename_into_place(const fs::path& tmp, const fs::path& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw OutputError(
        fmt::format("cannot rename {} to {}: {}", tmp.string(), path.string(), ec.message()));
  }
}

/// Writes what `produce` hands to its sink, piece by piece, to `path` through path.tmp, flushed
/// to the disk (fsync) before the rename: the file is either the old one (or absent) or the
/// whole new one.
void write_durably(
    const fs::path& path,
    const std::function<void(const std::function<void(std::string_view)>&)>& produce) {
  const fs::path tmp = fs::path(path).concat(".tmp");
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  auto fail = [&](const char* what) {
    const std::string why = std::strerror(errno);
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    throw OutputError(fmt::format("cannot {} {}: {}", what, tmp.string(), why));
  };
  if (fd < 0) fail("create");
  produce([&](std::string_view bytes) {
    for (std::size_t at = 0; at < bytes.size();) {
      const ssize_t n = ::write(fd, bytes.data() + at, bytes.size() - at);
      if (n < 0) {
        if (errno == EINTR) continue;
        fail("write");
      }
      at += static_cast<std::size_t>(n);
    }
  });
  if (::fsync(fd) != 0) fail("flush");
  if (::close(fd) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw OutputError(fmt::format("cannot write {}: {}", tmp.string(), why));
  }
  rename_into_place(tmp, path);
}

void write_durably(const fs::path& path, std::string_view bytes) {
  write_durably(path, [&](const std::function<void(std::string_view)>& sink) { sink(bytes); });
}

std::string file_name(int step) {
  return fmt::format("step_{:06d}.hckp", step);
}

}  // namespace

// ---------------------------------------------------------------------------------------------

CheckpointMesh checkpoint_mesh(const Mesh& mesh) {
  const Named r = regions_of(mesh);
  return {mesh_fingerprint(mesh), r.names, r.prints, mesh.n_nodes(), mesh.cells.size()};
}

std::optional<CheckpointMesh> checkpoint_mesh_of_parts(const Model& model) {
  const MeshPart& part = *model.part();
  const Mesh& m = model.mesh();
  // A part's own nodes are its first, in the whole order; the ranks' runs follow each other
  // (the numbering part_of_piece gives), and so do their cells and faces.
  std::vector<double> x, cells, regions;
  for (int n = 0; n < part.owned_nodes; ++n)
    x.insert(x.end(), {m.x[n].x(), m.x[n].y(), m.x[n].z()});
  for (int c = 0; c < m.cells.size(); ++c) {
    const auto nodes = m.cells.nodes(c);
    cells.push_back(static_cast<double>(m.cells.type[c]));
    cells.push_back(static_cast<double>(nodes.size()));
    for (int n : nodes) cells.push_back(part.global_node[n]);
  }
  for (const Region& r : m.regions) {
    const std::vector<int>& whole_index = r.dim == 3 ? part.global_cell : part.global_face;
    regions.push_back(static_cast<double>(r.cells.size()));
    for (int c : r.cells) regions.push_back(whole_index[c]);
    regions.push_back(static_cast<double>(r.nodes.size()));
    for (int n : r.nodes) regions.push_back(part.global_node[n]);
  }
  const auto all_x = gather_doubles(x), all_cells = gather_doubles(cells),
             all_regions = gather_doubles(regions);
  if (!par::root()) return std::nullopt;
  Mesh whole;
  for (const auto& v : all_x)
    for (std::size_t i = 0; i < v.size(); i += 3) whole.x.emplace_back(v[i], v[i + 1], v[i + 2]);
  std::vector<int> nodes;
  for (const auto& v : all_cells)
    for (std::size_t i = 0; i < v.size();) {
      const auto type = static_cast<CellType>(v[i]);
      nodes.assign(
          v.begin() + static_cast<std::ptrdiff_t>(i + 2),
          v.begin() + static_cast<std::ptrdiff_t>(i + 2 + static_cast<std::size_t>(v[i + 1])));
      whole.cells.add(type, nodes, 0);
      i += 2 + nodes.size();
    }
  whole.regions.resize(m.regions.size());
  for (const auto& v : all_regions) {
    std::size_t i = 0;
    for (std::size_t k = 0; k < m.regions.size(); ++k) {
      Region& r = whole.regions[k];
      r.dim = m.regions[k].dim;
      r.name = m.regions[k].name;
      for (auto n = static_cast<std::size_t>(v[i++]); n > 0; --n)
        r.cells.push_back(static_cast<int>(v[i++]));
      for (auto n = static_cast<std::size_t>(v[i++]); n > 0; --n)
        r.nodes.push_back(static_cast<int>(v[i++]));
    }
  }
  for (Region& r : whole.regions) {
    std::sort(r.nodes.begin(), r.nodes.end());
    r.nodes.erase(std::unique(r.nodes.begin(), r.nodes.end()), r.nodes.end());
  }
  return checkpoint_mesh(whole);
}

CheckpointFile checkpoint_of(const Model& model, const State& s, const RunMemory& run,
                             const CheckpointMesh* whole) {
  CheckpointFile f;
  if (model.part() && par::root() && !whole)
    throw std::logic_error("checkpoint_of: a distributed mesh needs the whole mesh's record");
  const CheckpointMesh mesh = whole          ? *whole
                              : model.part() ? CheckpointMesh{}
                                             : checkpoint_mesh(model.mesh());
  f.put("hencky", std::string(HENCKY_VERSION));
  f.put("title", model.spec().title);
  f.put("case", model.spec().file.string());
  f.put("ranks", static_cast<std::int64_t>(par::size()));
  f.put("mesh.fingerprint", mesh.fingerprint);
  f.put("mesh.nodes", static_cast<std::int64_t>(mesh.nodes));
  f.put("mesh.cells", static_cast<std::int64_t>(mesh.cells));
  put_named(f, "regions", Named{mesh.region_names, mesh.region_prints});
  put_named(f, "materials", materials_of(model.spec()));
  f.put("time", s.time);
  const std::int64_t counts[3] = {run.steps, run.iterations, run.factorizations};
  f.put("counts", std::span<const std::int64_t>(counts));
  f.put("force_integral", s.force_integral);
  // Nodal data: whole on every rank, or gathered from a distributed mesh's owners.
  const auto nodal = [&](const std::string& key, const std::vector<double>& v, int width) {
    put_nodal(f, key, model, v, width);
  };
  nodal("u", s.u, 3);
  nodal("nodal_temperature", s.nodal_temperature, 1);
  f.put("heat_flow", std::span<const double>(s.heat_flow));
  nodal("f_ext", s.f_ext, 3);
  nodal("f_int", s.f_int, 3);
  nodal("f_contact", s.f_contact, 3);
  put_contact(f, "contact", s.contact, model);
  // Point data, in the whole mesh's order.
  const auto off = global_offsets(model);
  f.put("points", static_cast<std::int64_t>(model.total_points()));
  put_points(f, "points.stress", model, off, 6,
             [&](int p, double* o) { put_voigt(o, s.stress[p]); });
  put_points(f, "points.temperature", model, off, 1,
             [&](int p, double* o) { o[0] = s.temperature[p]; });
  put_points(f, "points.constants", model, off, 3, [&](int p, double* o) {
    o[0] = s.constants[p].E, o[1] = s.constants[p].nu, o[2] = s.constants[p].alpha;
  });
  put_points(f, "points.plastic_strain", model, off, 6,
             [&](int p, double* o) { put_voigt(o, s.plastic_strain[p]); });
  put_points(f, "points.scalars", model, off, 4, [&](int p, double* o) {
    o[0] = s.eps_p_eq[p], o[1] = s.eps_ep[p], o[2] = s.eps_ep_max[p], o[3] = s.flowing[p];
  });
  // The equilibrium iteration's memory.
  const EquilibriumMemory& eq = run.equilibrium;
  const auto& dofs = model.dofs();
  std::vector<double> du(dofs.n_dofs(), 0.0);
  if (!eq.last_du.empty())
    for (int i = 0; i < dofs.n_dofs(); ++i)
      if (const int k = dofs.eq[i]; k >= 0) du[i] = eq.last_du[k];
  nodal("equilibrium.last_du", du, 3);
  f.put("equilibrium.last_dt", eq.last_dt);
  f.put("equilibrium.factorized", static_cast<std::int64_t>(eq.factorized));
  // A rank whose part holds no cell (more ranks than cells) has no tangents of its own.
  const bool tangents = par::any(!eq.tangents.empty());
  f.put("equilibrium.has_tangents", static_cast<std::int64_t>(tangents));
  if (tangents) {
    put_points(f, "equilibrium.tangents", model, off, tangent_width,
               [&](int p, double* o) { put_tangent(o, eq.tangents[p]); });
    if (eq.factorized)
      put_points(f, "equilibrium.assembled_tangents", model, off, tangent_width,
                 [&](int p, double* o) { put_tangent(o, eq.assembled_tangents[p]); });
  }
  put_contact(f, "equilibrium.assembled_contact", eq.assembled_contact, model);
  // The step targets still queued.
  std::vector<double> times;
  std::vector<std::int64_t> depths;
  for (const StepTarget& t : run.pending) times.push_back(t.time), depths.push_back(t.depth);
  f.put("pending.times", std::span<const double>(times));
  f.put("pending.depths", std::span<const std::int64_t>(depths));
  // The heat analysis.
  f.put("heat", static_cast<std::int64_t>(run.heat.has_value()));
  if (run.heat) {
    const HeatMemory& h = *run.heat;
    f.put("heat.snapshots", static_cast<std::int64_t>(h.snapshots.size()));
    for (std::size_t i = 0; i < h.snapshots.size(); ++i) {
      const HeatSnapshot& sn = h.snapshots[i];
      const std::string k = fmt::format("heat.snapshot.{}.", i);
      f.put(k + "time", sn.time);
      nodal(k + "T", sn.T, 1);
      f.put(k + "flow", std::span<const double>(sn.flow));
      f.put(k + "flow_now", std::span<const double>(sn.flow_now));
      f.put(k + "energy", std::span<const double>(sn.energy));
    }
    nodal("heat.R_last", h.R_last, 1);
    nodal("heat.S_last", h.S_last, 1);
    f.put("heat.committed", h.committed);
    const std::int64_t hc[3] = {h.steps, h.iterations, h.gmres_iterations};
    f.put("heat.counts", std::span<const std::int64_t>(hc));
  }
  return f;
}

Restart restore_run(const Model& model, const CheckpointFile& f, const CheckpointMesh* whole) {
  const Mesh& mesh = model.mesh();
  if (model.part() && !whole)
    throw std::logic_error("restore_run: a distributed mesh needs the whole mesh's record");
  const CheckpointMesh now = whole ? *whole : checkpoint_mesh(mesh);
  if (f.integer("mesh.nodes") != now.nodes || f.integer("mesh.cells") != now.cells ||
      f.integer("mesh.fingerprint") != now.fingerprint)
    changed(f, "mesh",
            fmt::format("the mesh {} is not the mesh the checkpoint was written with ({} nodes "
                        "and {} elements then, {} and {} now, or other coordinates or "
                        "connectivity)",
                        model.spec().mesh.file.filename().string(), f.integer("mesh.nodes"),
                        f.integer("mesh.cells"), now.nodes, now.cells));
  if (auto why = named_change(f, "regions", Named{now.region_names, now.region_prints}, "region");
      !why.empty())
    changed(f, "regions", why);
  if (auto why = named_change(f, "materials", materials_of(model.spec()), "material"); !why.empty())
    changed(f, "materials", why);
  const bool heat = f.integer("heat") != 0;
  if (heat != model.has_heat())
    changed(f, "heat",
            heat ? "the checkpoint's run had a heat section, the case has none"
                 : "the case has a heat section, the checkpoint's run had none");

  Restart restart;
  RunMemory& run = restart.run;
  State& s = restart.committed;
  const long long n_nodes = mesh.n_nodes();
  // A nodal array of `width` values a node: the file's whole one, or a part's nodes of it.
  // (Read where the file is, on a distributed restart: CheckpointFile::read_together.)
  const auto nodal = [&](const std::string& key, int width) {
    if (!model.part()) return f.f64(key, width * n_nodes);
    const auto& global = model.part()->global_node;
    std::vector<long long> start(n_nodes);
    for (long long i = 0; i < n_nodes; ++i) start[i] = width * static_cast<long long>(global[i]);
    return f.f64_runs(key, width * model.global_nodes(), start, std::vector<int>(n_nodes, width));
  };
  s.time = f.scalar("time");
  const auto& counts = f.i64("counts", 3);
  run.steps = static_cast<int>(counts[0]);
  run.iterations = static_cast<int>(counts[1]);
  run.factorizations = static_cast<int>(counts[2]);
  s.force_integral = f.scalar("force_integral");
  s.u = nodal("u", 3);
  s.nodal_temperature = nodal("nodal_temperature", 1);
  s.heat_flow =
      f.f64("heat_flow", heat ? static_cast<long long>(model.spec().heat.boundary.size()) : -1);
  s.f_ext = nodal("f_ext", 3);
  s.f_int = nodal("f_int", 3);
  s.f_contact = nodal("f_contact", 3);
  s.contact = get_contact(f, "contact", model);
  if (s.contact.size() != model.contacts().size())
    changed(f, "contact", "the case has contact surfaces, the checkpoint's run had none");

  const auto off = global_offsets(model);
  const long long n_all = off.back();
  if (f.integer("points") != n_all)
    changed(f, "mesh",
            fmt::format("the checkpoint holds {} integration points, the model has {}",
                        f.integer("points"), n_all));
  const int n = model.n_points();
  s.stress.resize(n);
  s.temperature.resize(n);
  s.constants.resize(n);
  s.plastic_strain.resize(n);
  s.eps_p_eq.resize(n);
  s.eps_ep.resize(n);
  s.eps_ep_max.resize(n);
  s.flowing.resize(n);
  scatter(f, "points.stress", model, off, 6,
          [&](int p, const double* v) { s.stress[p] = get_voigt(v); });
  scatter(f, "points.temperature", model, off, 1,
          [&](int p, const double* v) { s.temperature[p] = v[0]; });
  scatter(f, "points.constants", model, off, 3, [&](int p, const double* v) {
    s.constants[p] = ElasticConstants{v[0], v[1], v[2]};
  });
  scatter(f, "points.plastic_strain", model, off, 6,
          [&](int p, const double* v) { s.plastic_strain[p] = get_voigt(v); });
  scatter(f, "points.scalars", model, off, 4, [&](int p, const double* v) {
    s.eps_p_eq[p] = v[0], s.eps_ep[p] = v[1], s.eps_ep_max[p] = v[2];
    s.flowing[p] = v[3] != 0;
  });

  EquilibriumMemory& eq = run.equilibrium;
  const auto& dofs = model.dofs();
  const std::vector<double> du = nodal("equilibrium.last_du", 3);
  eq.last_dt = f.scalar("equilibrium.last_dt");
  if (eq.last_dt > 0) {
    eq.last_du.assign(dofs.n_free, 0.0);
    for (int i = 0; i < dofs.n_dofs(); ++i)
      if (const int k = dofs.eq[i]; k >= 0) eq.last_du[k] = du[i];
  }
  eq.factorized = f.integer("equilibrium.factorized") != 0;
  const bool tangents = f.integer("equilibrium.has_tangents") != 0;
  if (tangents != model.has_plasticity())
    changed(f, "materials", "the plasticity of the materials changed");
  if (tangents) {
    eq.tangents.resize(n);
    scatter(f, "equilibrium.tangents", model, off, tangent_width,
            [&](int p, const double* v) { eq.tangents[p] = get_tangent(v); });
    if (eq.factorized) {
      eq.assembled_tangents.resize(n);
      scatter(f, "equilibrium.assembled_tangents", model, off, tangent_width,
              [&](int p, const double* v) { eq.assembled_tangents[p] = get_tangent(v); });
    }
  }
  eq.assembled_contact = get_contact(f, "equilibrium.assembled_contact", model);
  if (eq.factorized && !model.contacts().empty() && eq.assembled_contact.empty())
    eq.factorized = false;  // assemble afresh (never the case for a checkpoint of ours)

  const auto& times = f.f64("pending.times");
  const auto& depths = f.i64("pending.depths", static_cast<long long>(times.size()));
  for (std::size_t i = 0; i < times.size(); ++i)
    run.pending.push_back({times[i], static_cast<int>(depths[i])});

  if (heat) {
    HeatMemory h;
    const auto n_snap = f.integer("heat.snapshots");
    const long long n_bc = static_cast<long long>(model.spec().heat.boundary.size());
    for (std::int64_t i = 0; i < n_snap; ++i) {
      const std::string k = fmt::format("heat.snapshot.{}.", i);
      HeatSnapshot sn;
      sn.time = f.scalar(k + "time");
      sn.T = nodal(k + "T", 1);
      sn.flow = f.f64(k + "flow", n_bc);
      sn.flow_now = f.f64(k + "flow_now");
      sn.energy = f.f64(k + "energy", n_bc);
      h.snapshots.push_back(std::move(sn));
    }
    h.R_last = nodal("heat.R_last", 1);
    h.S_last = nodal("heat.S_last", 1);
    h.committed = f.scalar("heat.committed");
    const auto& hc = f.i64("heat.counts", 3);
    h.steps = static_cast<int>(hc[0]);
    h.iterations = static_cast<int>(hc[1]);
    h.gmres_iterations = static_cast<int>(hc[2]);
    run.heat = std::move(h);
  }
  return restart;
}

// ---------------------------------------------------------------------------------------------

std::vector<CheckpointEntry> list_checkpoints(const fs::path& dir, const SourceLocation& where) {
  const fs::path index = dir / "checkpoints" / "index.csv";
  std::ifstream in(index);
  if (!in)
    throw InputError(where, fmt::format("{} holds no checkpoints ({} cannot be read): was it "
                                        "written with output.checkpoint: off?",
                                        dir.string(), index.string()));
  std::vector<CheckpointEntry> out;
  std::string line;
  int row = 0;
  while (std::getline(in, line)) {
    if (++row == 1 || line.empty()) continue;  // the header
    std::istringstream ss(line);
    std::string step, time, file;
    CheckpointEntry e;
    try {
      if (!std::getline(ss, step, ',') || !std::getline(ss, time, ',') || !std::getline(ss, file) ||
          file.empty() || file.find('/') != std::string::npos)
        throw std::invalid_argument("columns");
      e.step = std::stoi(step);
      e.time = std::stod(time);
    } catch (const std::exception&) {
      throw InputError(SourceLocation{index.string(), row, 0, ""},
                       "expected 'step,time,file' (the index hencky writes); the index is damaged");
    }
    e.file = dir / "checkpoints" / file;
    out.push_back(std::move(e));
  }
  if (out.empty())
    throw InputError(where, fmt::format("{} holds no checkpoints ({} lists none)", dir.string(),
                                        index.string()));
  return out;
}

CheckpointFile read_checkpoint(const fs::path& file) {
  const SourceLocation where{file.string(), 0, 0, ""};
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  std::ifstream in(file, std::ios::binary);
  if (ec || !in) throw InputError(where, "cannot read the checkpoint");
  std::string bytes(size, '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size)))
    throw InputError(where, "cannot read the checkpoint");
  return CheckpointFile::parse(bytes, file.string());
}

CheckpointWriter::CheckpointWriter(const Model& model, const fs::path& dir, Log& log,
                                   std::vector<CheckpointEntry> earlier,
                                   std::optional<CheckpointMesh> whole)
    : model_(model),
      dir_(dir / "checkpoints"),
      log_(log),
      whole_(std::move(whole)),
      entries_(std::move(earlier)) {
  if (!par::root()) return;
  fs::create_directories(dir_);
  if (!entries_.empty()) write_index();
}

bool CheckpointWriter::due(const StepReport& report) const {
  const int every = model_.spec().output.checkpoint_every();
  return every > 0 && report.step % every == 0;
}

void CheckpointWriter::write(const State& committed, const RunMemory& run) {
  if (model_.spec().output.checkpoint_every() == 0) return;
  const CheckpointFile f =
      checkpoint_of(model_, committed, run, whole_ ? &*whole_ : nullptr);  // collective
  const std::string name = file_name(run.steps);
  if (f.distributed()) {
    // Each rank writes its nodes' and points' values into the file itself: no rank gathers
    // the whole (docs/parallel.md). Through name.tmp, as write_durably.
    // Root's path: the output folder being written is root's (a name with its process id).
    std::string tmp = fs::path(dir_ / name).concat(".tmp").string();
    par::broadcast(tmp);
    f.write_together(tmp);  // collective
    if (!par::root()) return;
    rename_into_place(tmp, dir_ / name);
  } else {
    if (!par::root()) return;
    // Straight from the records to the file: no serialized copy (72 MB at 366k unknowns).
    write_durably(dir_ / name, [&](const auto& sink) { f.write(sink); });
  }
  std::erase_if(entries_, [&](const CheckpointEntry& e) { return e.step >= run.steps; });
  entries_.push_back({run.steps, committed.time, dir_ / name});
  ++written_;
  // The newest output.checkpoint_keep: the index first, then the files it no longer lists.
  const int keep = model_.spec().output.checkpoint_keep;
  std::vector<CheckpointEntry> dropped;
  if (keep > 0 && static_cast<int>(entries_.size()) > keep) {
    dropped.assign(entries_.begin(), entries_.end() - keep);
    entries_.erase(entries_.begin(), entries_.end() - keep);
  }
  write_index();
  for (const auto& e : dropped) {
    std::error_code ec;
    fs::remove(e.file, ec);
  }
  log_.detail("checkpoint {} (t = {:g})", name, committed.time);
}

void CheckpointWriter::write_index() const {
  std::string s = "step,time,file\n";
  for (const auto& e : entries_)
    s += fmt::format("{},{:.17g},{}\n", e.step, e.time, e.file.filename().string());
  write_durably(dir_ / "index.csv", s);
}

}  // namespace hencky
