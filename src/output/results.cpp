// The run's outputs but the fields files (results.hpp): the output directory and its checks,
// history.csv, the values summary.json reports, the report, a restart's outputs carried over.
#include "output/results.hpp"

#include <fmt/format.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <sstream>
#include <type_traits>
#include <variant>

#include "contact/surface_type.hpp"
#include "core/error.hpp"
#include "output/tensor_order.hpp"
#include "parallel/mpi.hpp"

namespace hencky {
namespace fs = std::filesystem;
using namespace tensor_order;

namespace {
/// A probe's strains in the order of strain_fields.
std::array<const Voigt*, 4> strains_of(const ProbeValues& v) {
  return {&v.strain, &v.elastic_strain, &v.plastic_strain, &v.thermal_strain};
}
/// The rigid surface where it starts (its `motion` moves it), for summary.json: what
/// scripts/render.py needs to draw it, as its type describes it (contact/surface_type.hpp).
nlohmann::json surface_json(const SurfaceParameters& surface) {
  nlohmann::json j = nlohmann::json::object();
  // (a pair, not a structured binding: clang 14, the sanitizer stage's, cannot capture one)
  for (const auto& entry : surface_type(surface.type).describe(surface)) {
    const std::string& key = entry.first;
    std::visit(
        [&j, &key](const auto& v) {
          if constexpr (std::is_same_v<std::decay_t<decltype(v)>, Vec3>)
            j[key] = nlohmann::json::array({v.x(), v.y(), v.z()});
          else
            j[key] = v;
        },
        entry.second);
  }
  return j;
}

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
  const OutputSpec& out = model_.spec().output;
  if (!out.deck_requests.empty() && par::size() > 1)
    // On several ranks the nodes and points are spread over them (a distributed mesh holds a
    // part on each): the deck's files would hold root's share alone.
    log_.warn(
        fmt::format("{}{}{} written by a run on one MPI rank only; this run on {} ranks "
                    "writes the fields, history.csv and summary.json",
                    out.deck_dat.empty() ? "" : out.deck_dat + " is",
                    !out.deck_dat.empty() && !out.deck_frd.empty() ? " and " : "",
                    out.deck_frd.empty() ? "" : out.deck_frd + " is", par::size()));
  else if (!out.deck_requests.empty())
    deck_files_ = std::make_unique<DeckFiles>(model_, work_dir_);
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
  // The point law's internal variables at the probes (a tensor in ParaView's order).
  for (const auto& p : model_.probes())
    for (const LawVariable& var : model_.law_variables()) {
      if (var.size == 1) h << ',' << p.spec->name << '.' << var.name;
      if (var.size == 6)
        for (auto c : paraview_names) h << ',' << p.spec->name << '.' << var.name << '.' << c;
    }
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
  deck_files_.reset();
  std::error_code ec;
  fs::remove_all(work_dir_, ec);
  finished_ = true;
}

/// The point law's internal variables at the probes (Model::law_variables), after every other
/// column: a tensor in ParaView's order.
void ResultWriter::write_law_values(const std::vector<ProbeValues>& probe_row,
                                    nlohmann::json& probes) {
  for (std::size_t i = 0; i < probe_row.size(); ++i) {
    auto& j = probes[model_.probes()[i].spec->name];
    std::size_t at = 0;
    for (const LawVariable& var : model_.law_variables()) {
      const double* x = probe_row[i].internal.data() + at;
      for (int c = 0; c < var.size; ++c) {
        const double value = x[var.size == 6 ? paraview_order[c] : c];
        history_ << fmt::format(",{:.17g}", value);
        if (var.size == 6)
          j[var.name][paraview_names[c]] = value;
        else
          j[var.name] = value;
      }
      at += var.size;
    }
  }
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
    j["surface"] = surface_json(model_.contacts()[k].spec->surface);
  }
  write_law_values(probe_row, probes);
  history_ << '\n';
  history_.flush();
  if (!history_)
    throw OutputError(fmt::format("cannot write history.csv in {}: {}", work_dir_.string(),
                                  errno ? std::strerror(errno) : "the stream failed"));
  final_values_ = {{"probes", probes}, {"reactions", reaction_json}, {"contact", contact_json}};
  if (model_.has_heat()) final_values_["heat_flows"] = heat_json;
  remember(values, report);
}

void ResultWriter::remember(const StepValues& values, const StepReport& report) {
  const double time = report.time;
  const YieldExcess& excess = report.yield_excess;
  // A later step's value counts only when it exceeds the peak by more than round-off (a
  // perfectly plastic point stays at σ_y to its last bits): the time is the first that reached it.
  const auto keep = [&](Peak& peak, const StepValues::Largest& now) {
    if (now.value > peak.at.value + 1e-12 * std::abs(peak.at.value)) peak = {now, time};
  };
  keep(peak_von_mises_, values.von_mises);
  keep(peak_displacement_, values.displacement);
  keep(peak_eps_p_eq_, values.eps_p_eq);
  const PointLargest& pv = report.point_von_mises;
  if (pv.value > -INFINITY) keep(peak_point_von_mises_, {pv.value, pv.node, pv.x});
  // The first step whose excess is largest (none: the first plastic step, at 0).
  if (excess.value > -INFINITY && (peak_yield_excess_.at.value == -1 ||
                                   excess.value > std::max(peak_yield_excess_.at.value, 0.0)))
    peak_yield_excess_ = {{std::max(excess.value, 0.0), excess.node, excess.x}, time};
  peak_contact_.resize(values.contacts.size(), {-INFINITY, 0.0});
  for (std::size_t b = 0; b < values.contacts.size(); ++b)
    if (values.contacts[b].force > peak_contact_[b].first)
      peak_contact_[b] = {values.contacts[b].force, time};
  balance_time_ = time;
  balance_ = values.balance;
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
  if (peak_yield_excess_.at.value >= 0) j["largest_yield_excess"] = peak(peak_yield_excess_);
  if (peak_point_von_mises_.at.value >= 0) j["point_von_mises"] = peak(peak_point_von_mises_);
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
  // A heat analysis alone (HeatSpec::only) has no stresses, displacements or forces to report.
  if (balance_time_ < 0 || model_.spec().heat.only) return lines;
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
  if (peak_point_von_mises_.at.value >= 0)
    lines.push_back(fmt::format("largest von Mises stress at an integration point {:.4g} {}",
                                peak_point_von_mises_.at.value, where(peak_point_von_mises_)));
  if (peak_yield_excess_.at.value >= 0)
    lines.push_back(fmt::format("largest yield excess σ̃/σ̃_y − 1 {:.3g} {}",
                                peak_yield_excess_.at.value, where(peak_yield_excess_)));
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

void ResultWriter::iterate_done(const IterateReport& r, const State& trial) {
  const StepValues values = step_values(model_, trial, recover_fields(model_, trial, false));
  if (!iterations_.is_open()) {
    iterations_.open(work_dir_ / "iterations.csv");
    iterations_ << "attempt,time,iteration,residual,delta_sigma,delta_epsilon,plastic_points";
    for (const auto& p : model_.probes()) {
      for (auto c : paraview_names) iterations_ << ',' << p.spec->name << ".stress." << c;
      iterations_ << ',' << p.spec->name << ".equivalent_elastoplastic_strain";
    }
    iterations_ << '\n';
  }
  iterations_ << fmt::format("{},{:.17g},{},{:.17g},{:.17g},{:.17g},{}", r.attempt, r.time,
                             r.iteration, r.residual, r.delta_sigma, r.delta_eps, r.plastic_points);
  for (const ProbeValues& v : values.probes) {
    for (int c = 0; c < 6; ++c) iterations_ << fmt::format(",{:.17g}", v.stress[paraview_order[c]]);
    iterations_ << fmt::format(",{:.17g}", v.eps_ep);
  }
  iterations_ << '\n';
  // A row that cannot be written (a full disk) does not stop the step: the step's own outputs
  // then fail and stop the run (write_outputs).
}

void ResultWriter::step_done(const StepReport& report, const State& state,
                             const RecoveredFields& fields) {
  // The fields' writing is collective on several ranks: a history that cannot be written must
  // not keep root from it.
  const StepValues values = step_values(model_, state, fields);  // collective
  std::exception_ptr history_failure;
  try {
    write_history(report, state, values);
    if (deck_files_) deck_files_->step_done(report, state, fields);
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
  std::vector<double> times;  // of the converged steps up to the restart's
  {
    std::ifstream in(old / "history.csv");
    std::string line;
    if (in && std::getline(in, line)) {
      const bool same = line + '\n' == header_;
      while (std::getline(in, line)) {
        if (line.empty()) continue;
        int step = 0;
        double time = 0;
        if (std::sscanf(line.c_str(), "%d,%lf", &step, &time) != 2 || step > steps) continue;
        times.push_back(time);
        if (same) history_ << line << '\n';
      }
      if (same) {
        history_.flush();
      } else {
        link_or_copy(old / "history.csv", work_dir_ / "history-before-restart.csv");
        log_.warn(
            "the history's columns changed with the case (its output section): history.csv "
            "starts at the restart, and the rows before it are in history-before-restart.csv");
      }
    }
  }
  // A deck's MODEL.dat and MODEL.frd up to the restart, its print frequencies counted on.
  if (deck_files_ && !times.empty()) deck_files_->continue_from(old, times.back(), times);
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
  deck_files_.reset();  // MODEL.frd's closing line
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
