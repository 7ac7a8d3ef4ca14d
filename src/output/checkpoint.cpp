// Checkpoints: the record of a run's memory and its fingerprints (checkpoint.hpp). Reading
// it back is checkpoint_restore.cpp's, the files of an output directory checkpoint_writer.cpp's.
#include "output/checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <functional>

#include "core/invariant.hpp"
#include "fem/reference_element.hpp"
#include "hencky/version.hpp"
#include "output/checkpoint_records.hpp"
#include "parallel/mpi.hpp"

namespace hencky {
using namespace checkpoint_records;
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
    // A point law's keys (none for the isotropic law: older checkpoints keep their prints).
    const LawParameters& law = m.plasticity->law;
    if (!law.law.empty()) {
      h.add(law.law);
      for (const auto& [key, groups] : law.keys) {
        h.add(key);
        h.add(groups.size());
        for (const auto& g : groups)
          for (const auto& [field, table] : g) {
            h.add(field);
            h.add(table);
          }
      }
    }
  }
  return h.value();
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : "\n") + n;
  return s;
}

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

void put_named(CheckpointFile& f, const std::string& key, const Named& n) {
  f.put(key + ".names", join(n.names));
  f.put(key + ".fingerprints", std::span<const std::int64_t>(n.prints));
}

// ---- Point data ---------------------------------------------------------------------------

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

// ---- Contact ---------------------------------------------------------------------------------

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

}  // namespace

// ---------------------------------------------------------------------------------------------

namespace checkpoint_records {

Named materials_of(const Case& c) {
  return named(c.materials, material_fingerprint);
}

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

}  // namespace checkpoint_records

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
  HENCKY_VERIFY(whole || !model.part() || !par::root(),
                "checkpoint_of: a distributed mesh needs the whole mesh's record");
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
  // The point laws' internal variables (material/point_law.hpp), where a law has any.
  if (const int w = model.law_state_size(); w > 0)
    put_points(f, "points.internal", model, off, w, [&](int p, double* o) {
      std::copy_n(s.internal.begin() + static_cast<std::ptrdiff_t>(p) * w, w, o);
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

}  // namespace hencky
