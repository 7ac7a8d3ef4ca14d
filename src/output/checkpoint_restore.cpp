// Reading a checkpoint back (checkpoint.hpp): the checks that the case is the checkpoint's run,
// the run's memory restored from the records, and the checkpoints of an output directory.
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <sstream>

#include "core/error.hpp"
#include "core/invariant.hpp"
#include "output/checkpoint.hpp"
#include "output/checkpoint_records.hpp"

namespace hencky {
namespace fs = std::filesystem;
using namespace checkpoint_records;
namespace {

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

/// Throws InputError (changed()) unless the model's mesh, regions, materials and heat section are
/// those the checkpoint was written with. Returns whether its run had a heat analysis.
bool check_same_model(const Model& model, const CheckpointFile& f, const CheckpointMesh* whole) {
  HENCKY_VERIFY(whole || !model.part(),
                "restore_run: a distributed mesh needs the whole mesh's record");
  const CheckpointMesh now = whole ? *whole : checkpoint_mesh(model.mesh());
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
  return heat;
}

/// A nodal array of `width` values a node: the file's whole one, or a part's nodes of it.
/// (Read where the file is, on a distributed restart: CheckpointFile::read_together.)
std::vector<double> read_nodal(const CheckpointFile& f, const Model& model, const std::string& key,
                               int width) {
  const long long n_nodes = model.mesh().n_nodes();
  if (!model.part()) return f.f64(key, width * n_nodes);
  const auto& global = model.part()->global_node;
  std::vector<long long> start(n_nodes);
  for (long long i = 0; i < n_nodes; ++i) start[i] = width * static_cast<long long>(global[i]);
  return f.f64_runs(key, width * model.global_nodes(), start, std::vector<int>(n_nodes, width));
}

/// The counts, the time and the nodal and contact state of the checkpoint's run.
void restore_nodal(const Model& model, const CheckpointFile& f, bool heat, State& s,
                   RunMemory& run) {
  s.time = f.scalar("time");
  const auto& counts = f.i64("counts", 3);
  run.steps = static_cast<int>(counts[0]);
  run.iterations = static_cast<int>(counts[1]);
  run.factorizations = static_cast<int>(counts[2]);
  s.force_integral = f.scalar("force_integral");
  s.u = read_nodal(f, model, "u", 3);
  s.nodal_temperature = read_nodal(f, model, "nodal_temperature", 1);
  s.heat_flow =
      f.f64("heat_flow", heat ? static_cast<long long>(model.spec().heat.boundary.size()) : -1);
  s.f_ext = read_nodal(f, model, "f_ext", 3);
  s.f_int = read_nodal(f, model, "f_int", 3);
  s.f_contact = read_nodal(f, model, "f_contact", 3);
  s.contact = get_contact(f, "contact", model);
  if (s.contact.size() != model.contacts().size())
    changed(f, "contact", "the case has contact surfaces, the checkpoint's run had none");
}

/// The state of the integration points this rank holds; `off` from global_offsets.
void restore_points(const Model& model, const CheckpointFile& f, const std::vector<long long>& off,
                    State& s) {
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
  const int w = model.law_state_size();
  s.internal.assign(static_cast<std::size_t>(n) * w, 0.0);
  if (w > 0)
    scatter(f, "points.internal", model, off, w, [&](int p, const double* v) {
      std::copy_n(v, w, s.internal.begin() + static_cast<std::ptrdiff_t>(p) * w);
    });
}

/// The equilibrium iteration's memory.
void restore_equilibrium(const Model& model, const CheckpointFile& f,
                         const std::vector<long long>& off, EquilibriumMemory& eq) {
  const auto& dofs = model.dofs();
  const std::vector<double> du = read_nodal(f, model, "equilibrium.last_du", 3);
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
    const int n = model.n_points();
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
}

/// The heat analysis's memory.
HeatMemory restore_heat(const Model& model, const CheckpointFile& f) {
  HeatMemory h;
  const auto n_snap = f.integer("heat.snapshots");
  const long long n_bc = static_cast<long long>(model.spec().heat.boundary.size());
  for (std::int64_t i = 0; i < n_snap; ++i) {
    const std::string k = fmt::format("heat.snapshot.{}.", i);
    HeatSnapshot sn;
    sn.time = f.scalar(k + "time");
    sn.T = read_nodal(f, model, k + "T", 1);
    sn.flow = f.f64(k + "flow", n_bc);
    sn.flow_now = f.f64(k + "flow_now");
    sn.energy = f.f64(k + "energy", n_bc);
    h.snapshots.push_back(std::move(sn));
  }
  h.R_last = read_nodal(f, model, "heat.R_last", 1);
  h.S_last = read_nodal(f, model, "heat.S_last", 1);
  h.committed = f.scalar("heat.committed");
  const auto& hc = f.i64("heat.counts", 3);
  h.steps = static_cast<int>(hc[0]);
  h.iterations = static_cast<int>(hc[1]);
  h.gmres_iterations = static_cast<int>(hc[2]);
  return h;
}

}  // namespace

Restart restore_run(const Model& model, const CheckpointFile& f, const CheckpointMesh* whole) {
  const bool heat = check_same_model(model, f, whole);
  Restart restart;
  RunMemory& run = restart.run;
  restore_nodal(model, f, heat, restart.committed, run);
  const auto off = global_offsets(model);
  restore_points(model, f, off, restart.committed);
  restore_equilibrium(model, f, off, run.equilibrium);
  // The step targets still queued.
  const auto& times = f.f64("pending.times");
  const auto& depths = f.i64("pending.depths", static_cast<long long>(times.size()));
  for (std::size_t i = 0; i < times.size(); ++i)
    run.pending.push_back({times[i], static_cast<int>(depths[i])});
  if (heat) run.heat = restore_heat(model, f);
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

}  // namespace hencky
