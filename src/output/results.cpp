#include "output/results.hpp"

#include <fmt/format.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <sstream>

#include "core/error.hpp"
#include "fem/reference_element.hpp"
#include "material/elastic.hpp"
#include "parallel/mesh_part.hpp"
#include "parallel/mpi.hpp"

namespace hencky {
namespace fs = std::filesystem;

namespace {
// Voigt {11,22,33,23,31,12} -> ParaView's XX YY ZZ XY YZ XZ.
constexpr std::array<int, 6> paraview_order{0, 1, 2, 5, 3, 4};
constexpr std::array<const char*, 6> paraview_names{"xx", "yy", "zz", "xy", "yz", "xz"};
constexpr std::array<const char*, 3> axes{"x", "y", "z"};
// The strains of issue 17, as tensors (ε_xy = γ_xy / 2) in ParaView's order like the stress.
// The probes' columns: ε = ε^e + ε^p + ε^th, all four.
constexpr std::array<const char*, 4> strain_fields{"strain", "elastic_strain", "plastic_strain",
                                                   "thermal_strain"};
double tensor_component(const Voigt& engineering, int c) {
  return engineering[paraview_order[c]] * (c < 3 ? 1.0 : 0.5);
}
/// A probe's strains in the order of strain_fields.
std::array<const Voigt*, 4> strains_of(const ProbeValues& v) {
  return {&v.strain, &v.elastic_strain, &v.plastic_strain, &v.thermal_strain};
}
/// The rigid surface where it starts (its `motion` moves it), for summary.json: what
/// scripts/render.py needs to draw it.
nlohmann::json surface_json(const ContactSpec& c) {
  const auto vec = [](const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); };
  switch (c.shape) {
    case ContactSpec::Shape::plane:
      return {{"shape", "plane"}, {"point", vec(c.point)}, {"normal", vec(c.normal)}};
    case ContactSpec::Shape::sphere:
      return {{"shape", "sphere"}, {"center", vec(c.center)}, {"radius", c.radius}};
    case ContactSpec::Shape::cylinder:
      return {{"shape", "cylinder"},
              {"point", vec(c.point)},
              {"axis", vec(c.axis)},
              {"radius", c.radius}};
    case ContactSpec::Shape::mesh:
      return {{"shape", "mesh"}, {"file", c.file.string()}, {"scale", c.scale}};
  }
  return {};
}
}  // namespace

std::vector<Voigt> recover_nodal_stress(const Model& model, const State& state) {
  return recover_fields(model, state).nodal_stress;
}

namespace {
/// The shape functions of the probe's cell at the probe.
template <class F>
void at_probe(const Model& model, const Probe& probe, F&& f) {
  const auto& mesh = model.mesh();
  const auto nodes = mesh.cells.nodes(probe.cell);
  double N[max_cell_nodes];
  shape_values(mesh.cells.type[probe.cell], probe.xi, N);
  for (std::size_t a = 0; a < nodes.size(); ++a) f(N[a], nodes[a]);
}
}  // namespace

ProbeValues probe_values(const Model& model, const Probe& probe, const State& state,
                         const std::vector<Voigt>& nodal_stress,
                         std::span<const double> nodal_eps_p_eq) {
  ProbeValues v;
  at_probe(model, probe, [&](double N, int n) {
    v.displacement += N * Vec3(state.u[3 * n], state.u[3 * n + 1], state.u[3 * n + 2]);
    v.stress += N * nodal_stress[n];
    v.temperature += N * state.nodal_temperature[n];
    if (!nodal_eps_p_eq.empty()) v.equivalent_plastic_strain += N * nodal_eps_p_eq[n];
  });
  v.von_mises = von_mises(v.stress);
  return v;
}

ProbeValues probe_values(const Model& model, const Probe& probe, const State& state,
                         const RecoveredFields& f) {
  ProbeValues v = probe_values(model, probe, state, f.nodal_stress, f.nodal_eps_p_eq);
  at_probe(model, probe, [&](double N, int n) {
    v.strain += N * f.nodal_strain[n];
    v.elastic_strain += N * f.nodal_elastic_strain[n];
    v.thermal_strain += N * f.nodal_thermal_strain[n];
    if (!f.nodal_plastic_strain.empty()) v.plastic_strain += N * f.nodal_plastic_strain[n];
    if (!f.nodal_eps_ep.empty()) v.eps_ep += N * f.nodal_eps_ep[n];
  });
  return v;
}

std::vector<Vec3> region_reactions(const Model& model, const State& state) {
  std::vector<Vec3> out;
  const Partition& part = model.partition();
  for (const auto& r : model.reaction_regions()) {
    if (!r.force) continue;
    Vec3 f = Vec3::Zero();
    for (int n : r.region->nodes) {
      if (part.node_owner[n] != part.rank) continue;  // another rank's share
      for (int d = 0; d < 3; ++d)
        f[d] += state.f_int[3 * n + d] - state.f_ext[3 * n + d] - state.f_contact[3 * n + d];
    }
    out.push_back(f);
  }
  return out;
}

std::vector<ContactTotals> contact_totals(const Model& model, const State& state) {
  std::vector<ContactTotals> out;
  for (std::size_t b = 0; b < model.contacts().size(); ++b)
    out.push_back(contact_totals(model.contacts()[b], state.contact[b], state.u));
  return out;
}

namespace {
/// f(x) for each number of a probe's values (a const or a mutable ProbeValues), in one fixed
/// order: for the sum over the ranks.
template <class V, class F>
void each_number(V& v, F&& f) {
  for (int d = 0; d < 3; ++d) f(v.displacement[d]);
  for (int c = 0; c < 6; ++c) f(v.stress[c]);
  f(v.von_mises);
  f(v.temperature);
  f(v.equivalent_plastic_strain);
  for (auto* e : {&v.strain, &v.elastic_strain, &v.plastic_strain, &v.thermal_strain})
    for (int c = 0; c < 6; ++c) f((*e)[c]);
  f(v.eps_ep);
}
}  // namespace

StepValues step_values(const Model& model, const State& state, const RecoveredFields& fields) {
  const Partition& part = model.partition();
  StepValues out;
  // Probes: the owner of the probe's cell evaluates, the others give zeros.
  const auto& probes = model.probes();
  std::vector<double> probe_numbers;
  for (const Probe& p : probes) {
    const ProbeValues v = p.cell >= 0 && part.cell_owner[p.cell] == part.rank
                              ? probe_values(model, p, state, fields)
                              : ProbeValues{};
    each_number(v, [&](double x) { probe_numbers.push_back(x); });
  }
  // Reactions and the contacts' sums (force, nodes, resultant) over each rank's own nodes; the
  // contacts' largest values over all.
  const std::vector<Vec3> reactions = region_reactions(model, state);
  const auto& bodies = model.contacts();
  std::vector<double> sums, largest;
  for (const Vec3& r : reactions) sums.insert(sums.end(), {r.x(), r.y(), r.z()});
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const ContactTotals t =
        contact_totals(bodies[b], state.contact[b], state.u, &part.node_owner, part.rank);
    sums.insert(sums.end(), {t.force, static_cast<double>(t.nodes), t.resultant.x(),
                             t.resultant.y(), t.resultant.z()});
    largest.insert(largest.end(), {t.max_penetration, t.max_penetration_relative, t.max_pressure});
  }
  sums.insert(sums.end(), probe_numbers.begin(), probe_numbers.end());
  // Over each rank's own nodes: the balance (reactions, loads, contact forces and Σ |F_int|,
  // the scale of the forces), and the largest nodal values, each as 5 numbers: the value, the
  // node's number and its position.
  double balance[10] = {};
  std::array<double, 15> mine;
  for (int k = 0; k < 3; ++k) mine[5 * k] = -1;
  const bool plastic = !fields.nodal_eps_p_eq.empty();
  const Mesh& mesh = model.mesh();
  for (int n = 0; n < mesh.n_nodes(); ++n) {
    if (part.node_owner[n] != part.rank) continue;
    const std::size_t i = 3 * static_cast<std::size_t>(n);
    for (int d = 0; d < 3; ++d) {
      balance[d] += state.f_int[i + d] - state.f_ext[i + d] - state.f_contact[i + d];
      balance[3 + d] += state.f_ext[i + d];
      balance[6 + d] += state.f_contact[i + d];
    }
    balance[9] += Vec3(state.f_int[i], state.f_int[i + 1], state.f_int[i + 2]).norm();
    const double v[3] = {von_mises(fields.nodal_stress[n]),
                         Vec3(state.u[i], state.u[i + 1], state.u[i + 2]).norm(),
                         plastic ? fields.nodal_eps_p_eq[n] : -1.0};
    for (int k = 0; k < 3; ++k)
      if (v[k] > mine[5 * k]) {
        mine[5 * k] = v[k];
        mine[5 * k + 1] = static_cast<double>(mesh.node_tag[n]);
        for (int d = 0; d < 3; ++d) mine[5 * k + 2 + d] = mesh.x[n][d];
      }
  }
  sums.insert(sums.end(), balance, balance + 10);
  par::sum_to_root(std::span<double>(sums));
  par::max_in_place(std::span<double>(largest));
  const double* s = sums.data();
  for (std::size_t k = 0; k < reactions.size(); ++k, s += 3)
    out.reactions.emplace_back(s[0], s[1], s[2]);
  for (std::size_t b = 0; b < bodies.size(); ++b, s += 5) {
    ContactTotals& t = out.contacts.emplace_back();
    t.force = s[0];
    t.nodes = static_cast<int>(std::lround(s[1]));
    t.resultant = Vec3(s[2], s[3], s[4]);
    t.max_penetration = largest[3 * b];
    t.max_penetration_relative = largest[3 * b + 1];
    t.max_pressure = largest[3 * b + 2];
  }
  out.probes.resize(probes.size());
  for (ProbeValues& v : out.probes) each_number(v, [&](double& x) { x = *s++; });
  out.balance = {Vec3(s[0], s[1], s[2]), Vec3(s[3], s[4], s[5]), Vec3(s[6], s[7], s[8]), s[9]};
  // The largest nodal values of all on root (the lowest rank's where two are equal).
  StepValues::Largest* best[3] = {&out.von_mises, &out.displacement, &out.eps_p_eq};
  const std::string bytes(reinterpret_cast<const char*>(mine.data()), sizeof mine);
  for (const std::string& b : par::gather_strings(bytes)) {
    if (b.size() != sizeof mine) continue;  // not root
    std::array<double, 15> theirs;
    std::memcpy(theirs.data(), b.data(), sizeof theirs);
    for (int k = 0; k < 3; ++k)
      if (theirs[5 * k] > best[k]->value) {
        best[k]->value = theirs[5 * k];
        best[k]->node = std::lround(theirs[5 * k + 1]);
        best[k]->x = Vec3(theirs[5 * k + 2], theirs[5 * k + 3], theirs[5 * k + 4]);
      }
  }
  return out;
}

HeatFlows heat_flows(const Model& model, const State& state) {
  HeatFlows out;
  const auto& bcs = model.spec().heat.boundary;
  const bool ignore_case = model.region_names_ignore_case();
  auto through = [&](const std::string& region, bool fixed_only) {
    double q = 0;
    for (std::size_t b = 0; b < bcs.size() && b < state.heat_flow.size(); ++b)
      if (Mesh::same_region_name(bcs[b].region, region, ignore_case) &&
          (!fixed_only || bcs[b].kind == HeatBoundarySpec::Kind::temperature))
        q += state.heat_flow[b];
    return q;
  };
  for (const auto& r : model.reaction_regions())
    if (r.heat) out.reactions.push_back(through(r.name, true));
  for (const auto& name : model.spec().output.heat_flows) out.flows.push_back(through(name, false));
  return out;
}

NodalContact nodal_contact(const Model& model, const State& state) {
  NodalContact out;
  const auto& bodies = model.contacts();
  if (bodies.empty()) return out;
  const int n = model.mesh().n_nodes();
  out.pressure.assign(n, 0.0);
  out.state.assign(n, 0.0);
  out.gap.assign(n, 0.0);
  std::vector<bool> seen(n, false);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    for (std::size_t i = 0; i < bodies[b].points.size(); ++i) {
      const ContactPoint& p = bodies[b].points[i];
      const ContactNode& s = state.contact[b][i];
      const double code = s.contact ? 1.0 : s.separation ? 2.0 : 0.0;
      out.state[p.node] = std::max(out.state[p.node], code);
      out.gap[p.node] = seen[p.node] ? std::min(out.gap[p.node], s.gap) : s.gap;
      seen[p.node] = true;
      if (s.contact)
        out.pressure[p.node] +=
            contact_force(s, contact_position(p, state.u)).dot(s.normal) / p.area;
    }
  return out;
}

namespace {
/// An existing output directory is replaced only when it is empty or holds hencky results, so
/// that a mistyped `-o` never deletes an unrelated folder.
bool replaceable(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return true;
  if (!fs::is_directory(dir, ec)) return false;
  if (fs::is_empty(dir, ec)) return true;
  return fs::exists(dir / "summary.json", ec) || fs::exists(dir / "results.pvd", ec) ||
         fs::exists(dir / "hencky.log", ec);
}

fs::path work_dir_of(const fs::path& final_dir) {
  fs::path w = final_dir;
  w += fmt::format(".partial-{}", ::getpid());
  return w;
}

/// The checks of check_output_dir that touch nothing.
void check_output_target(const fs::path& dir, const SourceLocation& where) {
  const fs::path parent = dir.parent_path();
  std::error_code ec;
  if (dir.filename().empty() || dir.filename() == "." || dir.filename() == "..")
    throw InputError(
        where, fmt::format("expected the path of an output directory, found {}", dir.string()));
  if (!parent.empty() && !fs::is_directory(parent, ec))
    throw InputError(where, fmt::format("the folder {} does not exist", parent.string()));
  if (!replaceable(dir))
    throw InputError(where, fmt::format("{} exists and is not a hencky output directory (no "
                                        "summary.json, results.pvd or hencky.log); it is left "
                                        "alone: choose another output directory",
                                        dir.string()));
}

/// Creates the work directory (after removing a stale one of the same name); an InputError at
/// `where` when the file system refuses (a read-only or virtual file system, no permission).
void create_work_dir(const fs::path& dir, const fs::path& work, const SourceLocation& where) {
  std::error_code ec;
  fs::remove_all(work, ec);
  if (!fs::create_directory(work, ec) || ec)
    throw InputError(where, fmt::format("cannot create the output directory {}: creating {} "
                                        "next to it failed ({}); choose a folder you can write to",
                                        dir.string(), work.filename().string(),
                                        ec ? ec.message() : "it exists"));
}

[[noreturn]] void cannot_write(const fs::path& dir, const fs::path& file,
                               const SourceLocation& where) {
  std::error_code ec;
  fs::remove_all(file.parent_path(), ec);
  throw InputError(where, fmt::format("cannot write {} into the output directory {}; choose a "
                                      "folder you can write to",
                                      file.filename().string(), dir.string()));
}
}  // namespace

void check_output_dir(const fs::path& dir, const SourceLocation& where) {
  check_output_target(dir, where);
  const fs::path work = work_dir_of(dir);
  create_work_dir(dir, work, where);
  const fs::path probe = work / "hencky.log";
  const bool written = static_cast<bool>(std::ofstream(probe) << "");
  std::error_code ec;
  fs::remove_all(work, ec);
  if (!written) cannot_write(dir, probe, where);
}

void check_output_space(const Model& model, const fs::path& dir, const SourceLocation& where,
                        Log& log) {
  struct statvfs fs_info {};
  const fs::path parent = dir.parent_path().empty() ? fs::path(".") : dir.parent_path();
  if (::statvfs(parent.c_str(), &fs_info) != 0) return;  // unknown: nothing to say
  const double free = static_cast<double>(fs_info.f_bavail) * fs_info.f_frsize;
  // The whole model's counts (a distributed one's are summed over its parts).
  const double nodes = static_cast<double>(model.global_nodes()),
               cells = static_cast<double>(model.global_cells()), points = model.total_points();
  // A fields file: 44 numbers per node (coordinates and the point fields), 9 per cell and the
  // connectivity; a checkpoint: 36 numbers per point of a plastic model (20 of an elastic one)
  // and 6 per unknown. Both within 10 % on the examples.
  const double vtu =
      8 * (44 * nodes + 11 * cells + static_cast<double>(model.global_connectivity()));
  const double checkpoint = 8 * ((model.has_plasticity() ? 36 : 20) * points + 6 * 3 * nodes);
  const auto& out = model.spec().output;
  const double steps = static_cast<double>(model.spec().solver.times.size());
  const double vtus = std::floor(steps / out.every) + 1;
  const int every_checkpoint = out.checkpoint_every();
  double checkpoints = every_checkpoint > 0 ? std::floor(steps / every_checkpoint) + 1 : 0;
  if (out.checkpoint_keep > 0) checkpoints = std::min<double>(checkpoints, out.checkpoint_keep + 1);
  const double first = vtu + (every_checkpoint > 0 ? checkpoint : 0),
               all = vtus * vtu + checkpoints * checkpoint;
  auto mb = [](double b) { return fmt::format("{:.1f} MB", b / 1e6); };
  if (free < first)
    throw InputError(where, fmt::format("the file system of {} has {} free; the outputs of one "
                                        "step need about {}: make room, or choose another folder",
                                        dir.string(), mb(free), mb(first)));
  if (free < all)
    log.warn(fmt::format(
        "the outputs of this run will take about {} ({} fields files of {}, {} checkpoints of "
        "{}); the file system of {} has {} free: when it is full the run stops (status 2) and "
        "keeps what it wrote (output.every, output.checkpoint and output.checkpoint_keep write "
        "less)",
        mb(all), vtus, mb(vtu), checkpoints, mb(checkpoint), dir.string(), mb(free)));
}

ResultWriter::ResultWriter(const Model& model, fs::path final_dir, Log& log,
                           const SourceLocation& where)
    : model_(model), final_dir_(std::move(final_dir)), log_(log) {
  check_output_target(final_dir_, where);
  work_dir_ = work_dir_of(final_dir_);
  create_work_dir(final_dir_, work_dir_, where);
  history_.open(work_dir_ / "history.csv");
  if (!history_) cannot_write(final_dir_, work_dir_ / "history.csv", where);
  log_.attach_file((work_dir_ / "hencky.log").string());
  std::ostringstream h;
  h << "step,time,iterations,residual";
  for (const auto& p : model_.probes()) {
    const auto& name = p.spec->name;
    for (auto ax : axes) h << ',' << name << ".displacement." << ax;
    for (auto c : paraview_names) h << ',' << name << ".stress." << c;
    h << ',' << name << ".von_mises," << name << ".equivalent_plastic_strain," << name
      << ".temperature";
  }
  for (const auto& r : model_.reaction_regions())
    if (r.force)
      for (auto ax : axes) h << ",reaction." << r.name << '.' << ax;
  for (const auto& r : model_.reaction_regions())
    if (r.heat) h << ",reaction." << r.name << ".heat";
  for (const auto& name : model_.spec().output.heat_flows) h << ",heat_flow." << name;
  for (const auto& c : model_.contacts())
    h << ",contact." << c.spec->name << ".force,contact." << c.spec->name << ".nodes";
  // Added after the contract's columns (scripts that read by name or position keep working).
  h << ",delta_sigma,delta_epsilon,factorizations,plastic_points";
  for (const auto& c : model_.contacts()) {
    for (auto ax : axes) h << ",contact." << c.spec->name << ".resultant." << ax;
    h << ",contact." << c.spec->name << ".max_penetration,contact." << c.spec->name
      << ".max_pressure";
  }
  for (const auto& p : model_.probes()) {
    for (const char* field : strain_fields)
      for (auto c : paraview_names) h << ',' << p.spec->name << '.' << field << '.' << c;
    h << ',' << p.spec->name << ".equivalent_elastoplastic_strain";
  }
  // Where each rigid surface is: its translation at the step (scripts/render.py draws it).
  for (const auto& c : model_.contacts())
    for (auto ax : axes) h << ",contact." << c.spec->name << ".motion." << ax;
  h << '\n';
  header_ = h.str();
  history_ << header_;
  pvd_ = std::make_unique<PvdWriter>(work_dir_ / "results.pvd");
  fields_ = std::make_unique<FieldsWriter>(model_, work_dir_);
  // A run that stops before its first step converges still reports the three groups (empty).
  final_values_ = {{"probes", nlohmann::json::object()},
                   {"reactions", nlohmann::json::object()},
                   {"contact", nlohmann::json::object()}};
}

ResultWriter::~ResultWriter() {
  if (!finished_ && !work_dir_.empty() && fs::exists(work_dir_))
    log_.info("results so far are in {}", work_dir_.string());
}

void ResultWriter::abandon() {
  std::error_code ec;
  fs::remove_all(work_dir_, ec);
  finished_ = true;
}

void ResultWriter::write_history(const StepReport& report, const State& state,
                                 const StepValues& values) {
  const auto& reactions = values.reactions;

  // history.csv and the values the summary reports
  history_ << fmt::format("{},{:.17g},{},{:.6e}", report.step, report.time, report.iterations,
                          report.residual);
  nlohmann::json probes = nlohmann::json::object(), reaction_json = nlohmann::json::object();
  const std::vector<ProbeValues>& probe_row = values.probes;
  for (std::size_t i = 0; i < model_.probes().size(); ++i) {
    const ProbeValues& v = probe_row[i];
    auto& j = probes[model_.probes()[i].spec->name];
    for (int d = 0; d < 3; ++d) {
      history_ << fmt::format(",{:.17g}", v.displacement[d]);
      j["displacement"][axes[d]] = v.displacement[d];
    }
    for (int c = 0; c < 6; ++c) {
      history_ << fmt::format(",{:.17g}", v.stress[paraview_order[c]]);
      j["stress"][paraview_names[c]] = v.stress[paraview_order[c]];
    }
    history_ << fmt::format(",{:.17g},{:.17g},{:.17g}", v.von_mises, v.equivalent_plastic_strain,
                            v.temperature);
    j["von_mises"] = v.von_mises;
    j["equivalent_plastic_strain"] = v.equivalent_plastic_strain;
    j["temperature"] = v.temperature;
    const auto strains = strains_of(v);
    for (std::size_t i = 0; i < strains.size(); ++i)
      for (int c = 0; c < 6; ++c)
        j[strain_fields[i]][paraview_names[c]] = tensor_component(*strains[i], c);
    j["equivalent_elastoplastic_strain"] = v.eps_ep;
  }
  {
    std::size_t k = 0;
    for (const auto& r : model_.reaction_regions())
      if (r.force) {
        for (int d = 0; d < 3; ++d) {
          history_ << fmt::format(",{:.17g}", reactions[k][d]);
          reaction_json[r.name][axes[d]] = reactions[k][d];
        }
        ++k;
      }
  }
  const HeatFlows heat = heat_flows(model_, state);
  nlohmann::json heat_json = nlohmann::json::object();
  {
    std::size_t k = 0;
    for (const auto& r : model_.reaction_regions())
      if (r.heat) {
        history_ << fmt::format(",{:.17g}", heat.reactions[k]);
        reaction_json[r.name]["heat"] = heat.reactions[k++];
      }
    for (std::size_t i = 0; i < heat.flows.size(); ++i) {
      history_ << fmt::format(",{:.17g}", heat.flows[i]);
      heat_json[model_.spec().output.heat_flows[i]] = heat.flows[i];
    }
  }
  const auto& contacts = values.contacts;
  nlohmann::json contact_json = nlohmann::json::object();
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const ContactTotals& t = contacts[k];
    history_ << fmt::format(",{:.17g},{}", t.force, t.nodes);
    auto& j = contact_json[model_.contacts()[k].spec->name];
    j["force"] = t.force;
    j["nodes"] = t.nodes;
    for (int d = 0; d < 3; ++d) j["resultant"][axes[d]] = t.resultant[d];
    j["max_penetration"] = t.max_penetration;
    j["max_pressure"] = t.max_pressure;
  }
  history_ << fmt::format(",{:.6e},{:.6e},{},{}", report.delta_sigma, report.delta_eps,
                          report.factorizations, report.plastic_points);
  for (const ContactTotals& t : contacts)
    history_ << fmt::format(",{:.17g},{:.17g},{:.17g},{:.6e},{:.17g}", t.resultant.x(),
                            t.resultant.y(), t.resultant.z(), t.max_penetration, t.max_pressure);
  for (const ProbeValues& v : probe_row) {
    for (const Voigt* e : strains_of(v))
      for (int c = 0; c < 6; ++c) history_ << fmt::format(",{:.17g}", tensor_component(*e, c));
    history_ << fmt::format(",{:.17g}", v.eps_ep);
  }
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Vec3 m = model_.contacts()[k].motion(report.time);
    history_ << fmt::format(",{:.17g},{:.17g},{:.17g}", m.x() + 0.0, m.y() + 0.0, m.z() + 0.0);
    auto& j = contact_json[model_.contacts()[k].spec->name];
    for (int d = 0; d < 3; ++d) j["motion"][axes[d]] = m[d] + 0.0;  // not -0
    j["surface"] = surface_json(*model_.contacts()[k].spec);
  }
  history_ << '\n';
  history_.flush();
  if (!history_)
    throw OutputError(fmt::format("cannot write history.csv in {}: {}", work_dir_.string(),
                                  errno ? std::strerror(errno) : "the stream failed"));
  final_values_ = {{"probes", probes}, {"reactions", reaction_json}, {"contact", contact_json}};
  if (model_.has_heat()) final_values_["heat_flows"] = heat_json;
  remember(report.time, values);
}

void ResultWriter::remember(double time, const StepValues& values) {
  // A later step's value counts only when it exceeds the peak by more than round-off (a
  // perfectly plastic point stays at σ_y to its last bits): the time is the first that reached it.
  const auto keep = [&](Peak& peak, const StepValues::Largest& now) {
    if (now.value > peak.at.value + 1e-12 * std::abs(peak.at.value)) peak = {now, time};
  };
  keep(peak_von_mises_, values.von_mises);
  keep(peak_displacement_, values.displacement);
  keep(peak_eps_p_eq_, values.eps_p_eq);
  peak_contact_.resize(values.contacts.size(), {-INFINITY, 0.0});
  for (std::size_t b = 0; b < values.contacts.size(); ++b)
    if (values.contacts[b].force > peak_contact_[b].first)
      peak_contact_[b] = {values.contacts[b].force, time};
  balance_time_ = time;
  balance_ = values.balance;
}

double StepValues::Balance::imbalance() const {
  // Σ|F_int| is the scale where the loads vanish and the reactions are round-off.
  const double scale = std::max({supports.norm(), loads.norm(), contact.norm(), force_scale});
  return scale > 0 ? (supports + loads + contact).norm() / scale : 0.0;
}

namespace {
nlohmann::json vec(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}
}  // namespace

nlohmann::json ResultWriter::report() const {
  nlohmann::json j = nlohmann::json::object();
  if (balance_time_ < 0) return j;  // no step converged
  const auto peak = [&](const Peak& p) -> nlohmann::json {
    return {
        {"value", p.at.value}, {"node", p.at.node}, {"position", vec(p.at.x)}, {"time", p.time}};
  };
  j["von_mises"] = peak(peak_von_mises_);
  j["displacement"] = peak(peak_displacement_);
  if (peak_eps_p_eq_.at.value >= 0) j["equivalent_plastic_strain"] = peak(peak_eps_p_eq_);
  j["balance"] = {{"time", balance_time_},
                  {"reactions", vec(balance_.supports)},
                  {"loads", vec(balance_.loads)},
                  {"contact", vec(balance_.contact)},
                  {"imbalance", balance_.imbalance()}};
  for (std::size_t b = 0; b < peak_contact_.size(); ++b)
    j["contact_force"][model_.contacts()[b].spec->name] = {{"value", peak_contact_[b].first},
                                                           {"time", peak_contact_[b].second}};
  return j;
}

std::vector<std::string> ResultWriter::report_lines() const {
  std::vector<std::string> lines;
  if (balance_time_ < 0) return lines;
  const auto where = [](const Peak& p) {
    return fmt::format("at node {} ({:.4g}, {:.4g}, {:.4g}), t = {:g}", p.at.node, p.at.x.x(),
                       p.at.x.y(), p.at.x.z(), p.time);
  };
  lines.push_back(fmt::format("largest von Mises stress {:.4g} {}", peak_von_mises_.at.value,
                              where(peak_von_mises_)));
  lines.push_back(fmt::format("largest displacement {:.4g} {}", peak_displacement_.at.value,
                              where(peak_displacement_)));
  if (peak_eps_p_eq_.at.value >= 0)
    lines.push_back(fmt::format("largest equivalent plastic strain {:.4g} {}",
                                peak_eps_p_eq_.at.value, where(peak_eps_p_eq_)));
  const auto v = [](const Vec3& x) {
    return fmt::format("({:.4g}, {:.4g}, {:.4g})", x.x(), x.y(), x.z());
  };
  lines.push_back(fmt::format("balance at t = {:g}: reactions {} + loads {}{} = 0 to {:.1e}",
                              balance_time_, v(balance_.supports), v(balance_.loads),
                              peak_contact_.empty() ? "" : " + contact " + v(balance_.contact),
                              balance_.imbalance()));
  for (std::size_t b = 0; b < peak_contact_.size(); ++b)
    lines.push_back(fmt::format("contact '{}': largest force {:.4g} at t = {:g}",
                                model_.contacts()[b].spec->name, peak_contact_[b].first,
                                peak_contact_[b].second));
  return lines;
}

void ResultWriter::step_done(const StepReport& report, const State& state,
                             const RecoveredFields& fields) {
  // The fields' writing is collective on several ranks: a history that cannot be written must
  // not keep root from it.
  const StepValues values = step_values(model_, state, fields);  // collective
  std::exception_ptr history_failure;
  try {
    write_history(report, state, values);
  } catch (const OutputError&) {
    history_failure = std::current_exception();
  }
  if (!report.write_fields) {
    if (history_failure) std::rethrow_exception(history_failure);
    return;
  }
  const std::string file = fields_->write(report, state, fields);
  if (history_failure) std::rethrow_exception(history_failure);
  pvd_->add(report.time, file);
}

FieldsWriter::FieldsWriter(const Model& model, fs::path dir)
    : model_(model), dir_(std::move(dir)), pieces_(par::size() > 1) {
  if (!pieces_) return;
  // The piece: this rank's part of the mesh, its own cells and the nodes they touch (its own,
  // then the ghosts).
  if (model_.partition().parts != par::size())
    throw std::logic_error("FieldsWriter: the model is not split over the ranks");
  if (model_.part()) return;  // the model's mesh is the piece (write() finds the ranks)
  MeshPart part = extract_part(model_.mesh(), model_.partition());
  cells_ = std::move(part.global_cell);
  nodes_ = std::move(part.global_node);
  cell_set_ = std::move(part.mesh.cells);
  x_ = std::move(part.mesh.x);
  node_tag_ = std::move(part.mesh.node_tag);
  cell_tag_ = cell_set_.tag;
  std::vector<char> has_cells(par::size(), 0);
  for (int owner : model_.partition().cell_owner) has_cells[owner] = 1;
  for (int r = 0; r < par::size(); ++r)
    if (has_cells[r]) ranks_with_cells_.push_back(r);
}

std::string FieldsWriter::write(const StepReport& report, const State& state,
                                const RecoveredFields& fields) {
  const std::string stem = fmt::format("step_{:04d}", report.step);
  heat_flux_ =
      model_.has_heat() ? nodal_heat_flux(model_, state.nodal_temperature) : std::vector<double>();
  if (!pieces_) {
    write_file(dir_ / (stem + ".vtu"), state, fields);
    return stem + ".vtu";
  }
  if (ranks_with_cells_.empty()) {
    // A distributed mesh: which ranks have cells (collective, as write() is; the constructor
    // runs on root alone first).
    std::vector<double> has_cells(par::size(), 0.0);
    has_cells[par::rank()] = model_.partition().owned_cells > 0;
    par::sum_in_place(std::span<double>(has_cells));
    for (int r = 0; r < par::size(); ++r)
      if (has_cells[r] > 0) ranks_with_cells_.push_back(r);
  }
  // Every rank with cells writes its piece into step_NNNN/; root then lists them.
  Layout layout;
  std::string failure;
  try {
    const fs::path folder = dir_ / stem;
    std::error_code ec;
    fs::create_directories(folder, ec);  // several ranks at once: one creates it
    if (ec && !fs::is_directory(folder))
      throw OutputError(fmt::format("cannot create {}: {}", folder.string(), ec.message()));
    if (model_.partition().owned_cells > 0)
      layout = write_file(folder / fmt::format("rank_{}.vtu", par::rank()), state, fields);
  } catch (const OutputError& e) {
    failure = e.what();
  }
  const std::vector<std::string> failures = par::gather_strings(failure);
  if (par::any(!failure.empty())) {
    std::string why;
    for (std::size_t r = 0; r < failures.size(); ++r)
      if (!failures[r].empty())
        why += fmt::format("{}rank {}: {}", why.empty() ? "" : "; ", r, failures[r]);
    throw OutputError(why.empty() ? std::string("another rank could not write its fields") : why);
  }
  if (!par::root()) return {};
  if (model_.partition().owned_cells == 0)  // root lists the pieces whether or not it has cells
    layout = write_file({}, state, fields);
  std::vector<std::string> pieces;
  for (int r : ranks_with_cells_) pieces.push_back(fmt::format("{}/rank_{}.vtu", stem, r));
  write_pvtu(dir_ / (stem + ".pvtu"), layout.point, layout.cell, layout.ints, true, pieces);
  return stem + ".pvtu";
}

FieldsWriter::Layout FieldsWriter::write_file(const fs::path& path, const State& state,
                                              const RecoveredFields& fields) {
  const auto& mesh = model_.mesh();
  // The model's own mesh: the whole one, or the part of a distributed one (which is the piece).
  const bool whole = !pieces_ || model_.part();
  const int n = whole ? mesh.n_nodes() : static_cast<int>(nodes_.size()),
            n_cells = whole ? mesh.cells.size() : static_cast<int>(cells_.size());
  const auto node = [&](int i) { return whole ? i : nodes_[i]; };
  const auto cell = [&](int i) { return whole ? i : cells_[i]; };
  // A nodal array of the whole model (`width` values a node), as the piece's: itself when whole.
  std::deque<std::vector<double>> gathered;  // stable addresses for the spans
  const auto at_nodes = [&](std::span<const double> v, int width) -> std::span<const double> {
    if (whole || v.empty()) return v;
    auto& out = gathered.emplace_back(static_cast<std::size_t>(width) * n);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < width; ++k)
        out[width * i + k] = v[static_cast<std::size_t>(width) * node(i) + k];
    return out;
  };
  const auto at_cells = [&](const std::vector<double>& v) -> std::span<const double> {
    if (whole) return v;
    auto& out = gathered.emplace_back(n_cells);
    for (int i = 0; i < n_cells; ++i) out[i] = v[cell(i)];
    return out;
  };
  const auto& nodal_stress = fields.nodal_stress;
  std::vector<double> stress(6 * n), vm(n), cell_stress(6 * n_cells);
  for (int i = 0; i < n; ++i) {
    for (int c = 0; c < 6; ++c) stress[6 * i + c] = nodal_stress[node(i)][paraview_order[c]];
    vm[i] = von_mises(nodal_stress[node(i)]);
  }
  std::vector<int> material(n_cells), region(n_cells);
  for (int i = 0; i < n_cells; ++i) {
    const int e = cell(i);
    for (int c = 0; c < 6; ++c) cell_stress[6 * i + c] = fields.cell_stress[e][paraview_order[c]];
    material[i] = model_.material_index(e);
    region[i] = mesh.cell_region[e];
  }
  // Fields of the contract that a model without plasticity or contact holds at zero.
  zeros_.assign(6 * static_cast<std::size_t>(n), 0.0);
  const std::span<const double> zero6(zeros_), zero1(zeros_.data(), n);
  // Strains as tensors (ε_xy = γ_xy / 2), in ParaView's order like the stress.
  const auto tensors = [&](const std::vector<Voigt>& nodal) {
    std::vector<double> out;
    if (nodal.empty()) return out;
    out.resize(6 * static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 6; ++c) out[6 * i + c] = tensor_component(nodal[node(i)], c);
    return out;
  };
  const std::vector<double> eps_p = tensors(fields.nodal_plastic_strain),
                            eps = tensors(fields.nodal_strain),
                            eps_e = tensors(fields.nodal_elastic_strain),
                            eps_th = tensors(fields.nodal_thermal_strain);
  const NodalContact contact = nodal_contact(model_, state);
  const auto or_zero = [&](const std::vector<double>& v) {
    return v.empty() ? zero1 : at_nodes(v, 1);
  };
  std::vector<VtuField> point_fields = {
      {"displacement", 3, at_nodes(state.u, 3)},
      {"stress", 6, stress},
      {"von_mises", 1, vm},
      {"temperature", 1, at_nodes(state.nodal_temperature, 1)},
      {"plastic_strain", 6, eps_p.empty() ? zero6 : std::span<const double>(eps_p)},
      {"equivalent_plastic_strain", 1, or_zero(fields.nodal_eps_p_eq)},
      {"contact_pressure", 1, or_zero(contact.pressure)},
      {"contact_state", 1, or_zero(contact.state)},
      {"contact_gap", 1, or_zero(contact.gap)},
      // after the contract's fields (issue 17)
      {"strain", 6, eps},
      {"elastic_strain", 6, eps_e},
      {"thermal_strain", 6, eps_th},
      {"equivalent_elastoplastic_strain", 1, or_zero(fields.nodal_eps_ep)},
  };
  if (model_.has_heat())
    point_fields.push_back({"heat_flux", 3, at_nodes(heat_flux_, 3)});  // issue 18
  std::vector<VtuField> cell_fields = {
      {"stress", 6, cell_stress},
      {"von_mises", 1, at_cells(fields.cell_von_mises)},
      {"equivalent_plastic_strain", 1, at_cells(fields.cell_eps_p_eq)},
      {"plastic_zone", 1, at_cells(fields.cell_plastic_zone)}};
  const VtuIntField int_fields[] = {{"material", material}, {"region", region}};
  if (!path.empty()) {
    if (!pieces_)
      write_vtu(path, mesh.x, mesh.cells, point_fields, cell_fields, int_fields);
    else if (whole)
      write_vtu(path, mesh.x, mesh.cells, point_fields, cell_fields, int_fields,
                VtuGlobalIds{mesh.node_tag, mesh.cells.tag});
    else
      write_vtu(path, x_, cell_set_, point_fields, cell_fields, int_fields,
                VtuGlobalIds{node_tag_, cell_tag_});
  }
  // The names and widths, for root's .pvtu (the data's spans die here).
  Layout layout;
  for (const auto& f : point_fields) layout.point.push_back({f.name, f.n_components, {}});
  for (const auto& f : cell_fields) layout.cell.push_back({f.name, f.n_components, {}});
  for (const auto& f : int_fields) layout.ints.push_back({f.name, {}});
  return layout;
}

namespace {
/// `to` as a hard link of `from`, or a copy where links are refused (another file system).
void link_or_copy(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::create_hard_link(from, to, ec);
  if (ec) fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}

/// The step number of a fields file "step_NNNN.vtu" or "step_NNNN.pvtu" (-1 for another name).
int step_of_file(const std::string& name) {
  int step = -1;
  char tail[8] = {};
  if (std::sscanf(name.c_str(), "step_%d.%5s", &step, tail) != 2 ||
      (std::string(tail) != "vtu" && std::string(tail) != "pvtu"))
    return -1;
  return step;
}
}  // namespace

std::vector<CheckpointEntry> ResultWriter::continue_from(
    const fs::path& old, int steps, const std::vector<CheckpointEntry>& checkpoints) {
  // history.csv: the rows up to the restart's step, when the columns are the same.
  {
    std::ifstream in(old / "history.csv");
    std::string line;
    if (in && std::getline(in, line)) {
      if (line + '\n' == header_) {
        while (std::getline(in, line)) {
          if (line.empty()) continue;
          int step = 0;
          if (std::sscanf(line.c_str(), "%d,", &step) == 1 && step <= steps)
            history_ << line << '\n';
        }
        history_.flush();
      } else {
        link_or_copy(old / "history.csv", work_dir_ / "history-before-restart.csv");
        log_.warn(
            "the history's columns changed with the case (its output section): history.csv "
            "starts at the restart, and the rows before it are in history-before-restart.csv");
      }
    }
  }
  // The fields' files and the series: the entries of results.pvd up to the restart's step.
  {
    std::ifstream in(old / "results.pvd");
    std::string line;
    std::vector<std::pair<double, std::string>> series;
    while (in && std::getline(in, line)) {
      const auto t = line.find("timestep=\""), f = line.find("file=\"");
      if (t == std::string::npos || f == std::string::npos) continue;
      const std::string file = line.substr(f + 6, line.find('"', f + 6) - (f + 6));
      const int step = step_of_file(file);
      if (step < 1 || step > steps || !fs::exists(old / file)) continue;
      link_or_copy(old / file, work_dir_ / file);
      // A run on several ranks: the pieces in step_NNNN/, whatever the ranks of this run.
      const fs::path pieces = old / fs::path(file).stem();
      if (fs::path(file).extension() == ".pvtu" && fs::is_directory(pieces)) {
        fs::create_directory(work_dir_ / pieces.filename());
        for (const auto& piece : fs::directory_iterator(pieces))
          link_or_copy(piece.path(), work_dir_ / pieces.filename() / piece.path().filename());
      }
      series.emplace_back(std::strtod(line.c_str() + t + 10, nullptr), file);
    }
    pvd_->adopt(std::move(series));
  }
  // The checkpoints up to the restart's.
  std::vector<CheckpointEntry> kept;
  fs::create_directories(work_dir_ / "checkpoints");
  for (const auto& e : checkpoints) {
    if (e.step > steps || !fs::exists(e.file)) continue;
    CheckpointEntry k = e;
    k.file = work_dir_ / "checkpoints" / e.file.filename();
    link_or_copy(e.file, k.file);
    kept.push_back(std::move(k));
  }
  return kept;
}

void ResultWriter::finish(nlohmann::json summary) {
  history_.close();
  {
    std::ofstream out(work_dir_ / "summary.json");
    out << summary.dump(2) << '\n';
  }
  // Move into place: the old directory is renamed away first, then removed.
  fs::path old;
  if (fs::exists(final_dir_)) {
    old = final_dir_;
    old += fmt::format(".old-{}", ::getpid());
    fs::rename(final_dir_, old);
  }
  fs::rename(work_dir_, final_dir_);
  if (!old.empty()) fs::remove_all(old);
  finished_ = true;
}

}  // namespace hencky
