// hencky: command line (see docs/cli.md and the contract CASE_FORMAT.md).
// Exit status: 0 converged, 1 bad input, 2 a step did not converge, 3 internal error,
// 4 interrupted (SIGINT or SIGTERM; the converged steps and a checkpoint are kept), 130 a second
// SIGINT stopped the run at once.
#include <fmt/format.h>
#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "core/interrupt.hpp"
#include "core/log.hpp"
#include "hencky/version.hpp"
#include "input/case_reader.hpp"
#include "input/gmsh_reader.hpp"
#include "input/load_case.hpp"
#include "linalg/blas_kernels.hpp"
#include "output/checkpoint.hpp"
#include "output/results.hpp"
#include "output/summary.hpp"
#include "parallel/mesh_part.hpp"
#include "parallel/mpi.hpp"
#include "parallel/partition.hpp"
#include "solve/analysis.hpp"
#include "solve/driver.hpp"

namespace {
using namespace hencky;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

long peak_memory_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<long>(u.ru_maxrss) * 1024;
}

// ---- Interruption -----------------------------------------------------------------------------
// The first SIGINT or SIGTERM asks the step loop to stop (core/interrupt.hpp): it finishes the
// output and the checkpoint of the last converged step and moves the results into place (exit
// status 4). A second one stops at once (status 130): the results so far, their checkpoints
// included, stay in the work directory the message names.
char interrupt_message[4096] = "";
char abort_message[4096] = "";
std::size_t interrupt_length = 0, abort_length = 0;

extern "C" void on_signal(int) {
  if (!request_interrupt()) {
    if (interrupt_length && par::root()) [[maybe_unused]]
      auto n = ::write(STDERR_FILENO, interrupt_message, interrupt_length);
    return;
  }
  if (abort_length && par::root()) [[maybe_unused]]
    auto n = ::write(STDERR_FILENO, abort_message, abort_length);
  ::_exit(130);
}

/// Installs the handlers (after PETSc, which installs its own at its start).
void catch_interrupts(const fs::path& work_dir) {
  const std::string first =
      "\nhencky: interrupted: finishing the output and the checkpoint of the last converged step "
      "(interrupt again to stop at once)\n";
  const std::string second = fmt::format(
      "\nhencky: stopped at once; the results so far and their checkpoints are in {} (hencky "
      "run CASE --restart {} continues)\n",
      work_dir.string(), work_dir.string());
  interrupt_length = std::min(first.size(), sizeof interrupt_message);
  std::memcpy(interrupt_message, first.data(), interrupt_length);
  abort_length = std::min(second.size(), sizeof abort_message);
  std::memcpy(abort_message, second.data(), abort_length);
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

/// Steps no rank may fail alone: every rank reports whether `f` threw, and all stop together
/// when one did. Root prints each rank's message once (ranks with the same message together).
/// Returns the exit status (0: all went well).
template <class F>
int together(F&& f) {
  int code = 0;
  std::string message;
  try {
    f();
  } catch (const InputError& e) {
    code = 1, message = std::string("error: ") + e.what();
  } catch (const std::exception& e) {
    code = 3, message = std::string("internal error: ") + e.what();
  }
  if (par::size() == 1) {
    if (code) std::cerr << message << "\n";
    return code;
  }
  const int worst = par::max(code);
  if (worst == 0) return 0;
  const auto messages = par::gather_strings(code ? message : std::string());
  if (par::root()) {
    std::map<std::string, std::vector<int>> ranks_of;
    for (std::size_t r = 0; r < messages.size(); ++r)
      if (!messages[r].empty()) ranks_of[messages[r]].push_back(static_cast<int>(r));
    for (const auto& [text, ranks] : ranks_of) {
      if (ranks.size() == messages.size()) {
        std::cerr << text << "\n";
        continue;
      }
      std::string who;
      for (int r : ranks) who += (who.empty() ? "" : ", ") + std::to_string(r);
      std::cerr << fmt::format("rank{} {}: {}\n", ranks.size() > 1 ? "s" : "", who, text);
    }
  }
  return worst;
}

/// The output directory given with -o: absolute, without a trailing separator ("out/" is
/// "out").
fs::path command_line_dir(const std::string& out_dir) {
  fs::path p = fs::absolute(out_dir).lexically_normal();
  return p.has_filename() ? p : p.parent_path();
}

/// --restart DIR [--from T]: the checkpoint to continue from, read on every rank (each its part
/// of it on a distributed mesh) and checked against the model; `earlier` gets DIR's checkpoints up
/// to it.
Restart restart_memory(const Model& model, const fs::path& dir, std::optional<double> from,
                       std::vector<CheckpointEntry>& earlier, Log& log,
                       const CheckpointMesh* whole) {
  const SourceLocation where{"", 0, 0, "--restart"};
  auto entries = list_checkpoints(dir, where);
  std::size_t pick = entries.size() - 1;  // the newest
  if (from) {
    const double eps = 1e-9 * std::max(1.0, std::abs(*from));
    auto it = std::find_if(entries.begin(), entries.end(), [&](const CheckpointEntry& e) {
      return std::abs(e.time - *from) <= eps;
    });
    if (it == entries.end()) {
      std::string times;
      for (const auto& e : entries)
        times += (times.empty() ? "" : ", ") + fmt::format("{:g}", e.time);
      throw InputError(SourceLocation{"", 0, 0, "--from"},
                       fmt::format("{} has no checkpoint at t = {:g}; it has checkpoints at t = {}",
                                   dir.string(), *from, times));
    }
    pick = static_cast<std::size_t>(it - entries.begin());
  }
  const CheckpointEntry& e = entries[pick];
  // On a distributed mesh no rank reads the file whole: each reads its nodes' and points'
  // values where they are (records from 4096 numbers, 32 kB, on).
  Restart r = restore_run(
      model,
      model.part() ? CheckpointFile::read_together(e.file.string(), 4096) : read_checkpoint(e.file),
      whole);
  log.info("restart: from {} (step {}, t = {:g})", e.file.string(), r.run.steps, r.committed.time);
  entries.resize(pick + 1);
  earlier = std::move(entries);
  return r;
}

/// Root's record of the whole mesh, on every rank (root's argument; the others' is ignored).
/// Collective.
std::optional<CheckpointMesh> broadcast_mesh_record(const std::optional<CheckpointMesh>& mine) {
  std::string text;
  if (par::root() && mine) {
    text = fmt::format("{} {} {}\n", mine->fingerprint, mine->nodes, mine->cells);
    for (std::size_t r = 0; r < mine->region_names.size(); ++r)
      text += fmt::format("{} {}\n", mine->region_prints[r], mine->region_names[r]);
  }
  par::broadcast(text);
  if (text.empty()) return std::nullopt;
  std::istringstream in(text);
  CheckpointMesh m;
  in >> m.fingerprint >> m.nodes >> m.cells;
  std::int64_t print = 0;
  std::string name;
  while (in >> print && in.get() == ' ' && std::getline(in, name)) {
    m.region_prints.push_back(print);
    m.region_names.push_back(name);
  }
  return m;
}

/// HENCKY_REPLICATED=1: every rank holds the whole mesh even where it could be distributed
/// (for comparisons: the memory and time of the two ways, bench/).
bool replicated_by_environment() {
  const char* v = std::getenv("HENCKY_REPLICATED");
  return v && *v && std::string(v) != "0";
}

/// A rank's model as run() loaded it, and what the log says of the whole.
struct Loaded {
  LoadedCase l;
  std::string mesh_line, parts_line;         // the whole mesh and its parts
  std::vector<std::string> contact_lines;    // the whole model's contact
  std::optional<CheckpointMesh> whole_mesh;  // root's record of it on a distributed mesh
};

/// The log's line on a distributed mesh's parts (`how`: words after the rank count).
/// Collective.
std::string describe_parts(const Model& m, const char* how) {
  const Partition& p = m.partition();
  return fmt::format(
      "distributed mesh: {} ranks,{} {} .. {} elements and {} .. {} nodes per rank (owned; "
      "{} .. {} with the ghosts)",
      par::size(), how, par::min(p.owned_cells), par::max(p.owned_cells), par::min(p.owned_nodes),
      par::max(p.owned_nodes), par::min(m.mesh().n_nodes()), par::max(m.mesh().n_nodes()));
}

/// The distributed way (docs/parallel.md, "Distributing the mesh"): root reads and checks the
/// whole model, as a serial run does, records what the log and the checkpoints need of it,
/// splits it and sends each rank its part; each rank binds the case to its part. Returns 0, or
/// the exit status when a rank failed (reported). Collective.
int load_distributed(std::unique_ptr<Case> spec, const fs::path& dir,
                     const SourceLocation& dir_where, Log& log, Loaded& out) {
  LoadedCase& l = out.l;
  LoadedCase whole;  // root's
  if (int code = together([&] {
        if (par::root()) {
          whole = load_case(std::move(spec), log);
          check_output_space(*whole.model, dir, dir_where, log);
        } else {
          l.spec = std::move(spec);
        }
      }))
    return code;
  std::unique_ptr<Mesh> mesh;
  std::vector<int> owner;
  if (par::root()) {
    const Model& m = *whole.model;
    out.mesh_line = fmt::format("{}; {} unknowns", describe_mesh(m.mesh()), m.dofs().n_free);
    owner = split_cells(m.mesh(), par::size());
    out.whole_mesh = checkpoint_mesh(m.mesh());
    out.contact_lines = describe_contact(m);
    mesh = std::make_unique<Mesh>(std::move(*whole.model).take_mesh());
    whole.model.reset();
    l.spec = std::move(whole.spec);
    l.mesh_seconds = whole.mesh_seconds;
    l.setup_seconds = whole.setup_seconds;
  }
  out.whole_mesh = broadcast_mesh_record(out.whole_mesh);  // every rank checks a restart with it
  MeshPart part = scatter_parts(mesh.get(), owner);
  mesh.reset();
  owner = {};
  if (int code = together([&] {
        Log quiet;  // root's whole model has said what there is to say
        quiet.silent = true;
        l.model = std::make_unique<Model>(*l.spec, std::move(part), quiet);
      }))
    return code;
  l.model->join();
  out.parts_line = describe_parts(*l.model, "");
  return 0;
}

/// The second distributed way (docs/parallel.md, "A mesh split into files"): mesh.split on
/// as many ranks as files. Each rank reads its own file and makes it its part (part_of_piece);
/// no rank reads or holds the whole mesh. The checks a whole model makes are made together
/// (Model::join), and the log's description and a checkpoint's record of the whole mesh are
/// summed and gathered. Returns 0, or the exit status when a rank failed (reported).
/// Collective.
int load_split(std::unique_ptr<Case> spec, const fs::path& dir, const SourceLocation& dir_where,
               Log& log, Loaded& out) {
  LoadedCase& l = out.l;
  l.spec = std::move(spec);
  const auto t_mesh = Clock::now();
  Mesh piece;
  if (int code = together([&] {
        MeshReadOptions options;
        options.piece = true;
        options.piece_number = par::rank() + 1;
        options.pieces = l.spec->mesh.pieces;
        options.scale = l.spec->mesh.scale;
        piece = read_gmsh(piece_file(l.spec->mesh, par::rank()), options);
      }))
    return code;
  MeshPart part;
  if (int code = together([&] { part = part_of_piece(std::move(piece)); })) return code;
  l.mesh_seconds = since(t_mesh);
  const auto t_setup = Clock::now();
  if (int code =
          together([&] { l.model = std::make_unique<Model>(*l.spec, std::move(part), log); }))
    return code;
  if (int code = together([&] { l.model->join(); })) return code;
  l.setup_seconds = since(t_setup);
  const Model& m = *l.model;
  std::vector<double> of_type(static_cast<int>(CellType::quad8) + 1, 0.0);  // exact counts
  for (CellType t : m.mesh().cells.type) ++of_type[static_cast<int>(t)];
  par::sum_in_place(std::span<double>(of_type));
  std::map<std::string, long long> by_type;
  for (std::size_t t = 0; t < of_type.size(); ++t)
    if (of_type[t] > 0)
      by_type[std::string(cell_name(static_cast<CellType>(t)))] = std::llround(of_type[t]);
  out.mesh_line =
      fmt::format("{}; {} unknowns", describe_counts(m.global_nodes(), m.global_cells(), by_type),
                  m.global_free());
  out.whole_mesh = broadcast_mesh_record(checkpoint_mesh_of_parts(m));
  out.parts_line = describe_parts(m, " each read its file of the split mesh;");
  out.contact_lines = describe_contact(m);
  return together([&] {
    if (par::root()) check_output_space(m, dir, dir_where, log);
  });
}

/// One rank, or the whole mesh on every rank (HENCKY_REPLICATED=1): each reads the case's mesh
/// and binds the whole model, and the ranks check that they read the same. Collective.
int load_replicated(std::unique_ptr<Case> spec, const fs::path& dir,
                    const SourceLocation& dir_where, Log& log, Loaded& out) {
  LoadedCase& l = out.l;
  if (int code = together([&] { l = load_case(std::move(spec), log); })) return code;
  const long long shape[3] = {l.model->mesh().n_nodes(), l.model->mesh().cells.size(),
                              l.model->dofs().n_free};
  for (long long v : shape)
    if (par::max(v) != par::min(v)) {
      if (par::root())
        std::cerr << "error: the ranks read different models (node, element or unknown "
                     "counts differ): give every rank the same case file and mesh\n";
      return 1;
    }
  if (int code = together([&] {
        if (par::root()) check_output_space(*l.model, dir, dir_where, log);
      }))
    return code;
  out.mesh_line =
      fmt::format("{}; {} unknowns", describe_mesh(l.model->mesh()), l.model->dofs().n_free);
  out.contact_lines = describe_contact(*l.model);
  return 0;
}

int run(const std::string& case_path, const std::string& out_dir, bool quiet,
        const std::string& petsc_options, const std::string& threads_warning,
        const std::string& restart, std::optional<double> from) {
  const auto t_start = Clock::now();
  Log log;
  log.quiet = quiet;
  log.silent = !par::root();
  if (!threads_warning.empty()) log.warn(threads_warning);
  if (const std::string note = blas_kernels_note(); !note.empty()) log.detail("{}", note);
  fs::path dir;  // the output directory, from -o or output.dir
  SourceLocation dir_where;
  // On several ranks the mesh is distributed (docs/parallel.md): root reads it and checks the
  // whole model, splits it and sends each rank its part; no rank holds the whole after.
  bool distribute = false;
  std::unique_ptr<Case> spec;
  long long case_print = 0;  // of the case file's text: the ranks must have read the same
  if (int code = together([&] {
        std::string text;  // the case file's, read once
        spec = std::make_unique<Case>(read_case(case_path, &text));
        dir = out_dir.empty() ? spec->output.dir : command_line_dir(out_dir);
        dir_where = out_dir.empty() ? spec->output.dir_where : SourceLocation{"", 0, 0, "-o"};
        // Before the mesh (Gmsh may mesh for minutes) and the analysis: root writes the
        // outputs, and can.
        if (par::root()) check_output_dir(dir, dir_where);
        distribute = par::size() > 1 && !replicated_by_environment();
        case_print = static_cast<long long>(std::hash<std::string>{}(text) >> 1);
      }))
    return code;
  // A distributed mesh is read by root alone: the ranks compare their case files instead.
  if (par::max(static_cast<int>(distribute)) != par::min(static_cast<int>(distribute)) ||
      (distribute && par::max(case_print) != par::min(case_print))) {
    if (par::root())
      std::cerr << "error: the ranks read different models (their case files differ): give "
                   "every rank the same case file and mesh\n";
    return 1;
  }
  Loaded loaded;
  // A split mesh on as many ranks as files: each rank reads its own.
  const bool own_files = distribute && spec->mesh.split && spec->mesh.pieces == par::size();
  std::string split_line;  // how a split mesh was read, where not each rank its own file
  if (distribute && spec->mesh.split && !own_files)
    split_line = fmt::format(
        "split mesh: root read its {} files and sent each rank its part ({} files on {} ranks)",
        spec->mesh.pieces, spec->mesh.pieces, par::size());
  if (int code = own_files    ? load_split(std::move(spec), dir, dir_where, log, loaded)
                 : distribute ? load_distributed(std::move(spec), dir, dir_where, log, loaded)
                              : load_replicated(std::move(spec), dir, dir_where, log, loaded))
    return code;
  LoadedCase& l = loaded.l;
  const std::string& mesh_line = loaded.mesh_line;
  const std::string& parts_line = loaded.parts_line;
  const std::vector<std::string>& contact_lines = loaded.contact_lines;
  const std::optional<CheckpointMesh>& whole_mesh = loaded.whole_mesh;
  const Model& model = *l.model;
  const Case& c = *l.spec;
  log.info("hencky {}: {}", HENCKY_VERSION, c.title);
  log.info("mesh: {}", mesh_line);
  if (!split_line.empty()) log.info("{}", split_line);
  if (!parts_line.empty()) log.info("{}", parts_line);
  for (const auto& line : contact_lines) log.info("{}", line);

  std::unique_ptr<LinearSystem> solver;
  std::unique_ptr<HeatSolver> heat;
  // The back ends' set-up (solver.linear: auto's factor estimate, PETSc's matrix) is setup.
  const auto t_solvers = Clock::now();
  if (int code = together([&] {
        solver = make_run_solver(*l.model, log, petsc_options);
        heat = make_heat_solver(*l.model, log, petsc_options);
      }))
    return code;
  l.setup_seconds += since(t_solvers);
  // After the solver: on several ranks it decided which integration points each rank holds.
  std::optional<Restart> resume;
  std::vector<CheckpointEntry> earlier;  // the checkpoints up to the restart's
  const fs::path restart_dir = restart.empty() ? fs::path() : command_line_dir(restart);
  if (int code = together([&] {
        if (!restart.empty())
          resume = restart_memory(model, restart_dir, from, earlier, log,
                                  whole_mesh ? &*whole_mesh : nullptr);
      }))
    return code;
  // Root writes every output but the other ranks' pieces of the fields files.
  std::unique_ptr<ResultWriter> writer;
  std::unique_ptr<CheckpointWriter> checkpoints;
  if (int code = together([&] {
        if (par::root()) {
          writer = std::make_unique<ResultWriter>(model, dir, log, dir_where);
          if (resume) earlier = writer->continue_from(restart_dir, resume->run.steps, earlier);
        }
        if (c.output.checkpoint_every() > 0)
          checkpoints = std::make_unique<CheckpointWriter>(
              model, writer ? writer->work_dir() : fs::path(), log, earlier, whole_mesh);
      }))
    return code;
  catch_interrupts(writer ? writer->work_dir() : fs::path());
  // The other ranks write their pieces of the fields files into root's work directory.
  std::string work_dir = writer ? writer->work_dir().string() : std::string();
  par::broadcast(work_dir);
  std::optional<PieceWriter> piece;
  if (!writer) piece.emplace(model, work_dir);
  Timings timings;
  AnalysisResult result;
  try {
    RunOptions options;
    options.resume = resume ? &*resume : nullptr;
    options.checkpoints = checkpoints.get();
    result =
        run_analysis(model, *solver, log, timings,
                     writer ? static_cast<StepObserver&>(*writer) : *piece, heat.get(), options);
  } catch (const InputError&) {
    if (writer) writer->abandon();  // bad input: nothing is overwritten or left behind
    throw;
  }
  // Peak resident memory of this process and, in a parallel run, the largest and the total
  // over the ranks (collective).
  RunFigures figures;
  const long long memory = peak_memory_bytes();
  figures.peak_memory_bytes = par::max(memory);
  if (par::size() > 1) figures.peak_memory_bytes_all_ranks = par::sum(memory);
  const int status = result.status == AnalysisStatus::converged     ? 0
                     : result.status == AnalysisStatus::interrupted ? 4
                                                                    : 2;
  if (!par::root()) return status;
  figures.title = c.title;
  figures.status = status;
  if (resume)
    figures.restart =
        RunFigures::From{restart_dir.string(), resume->run.steps, resume->committed.time};
  if (checkpoints) figures.checkpoints = checkpoints->written();
  figures.result = result;
  figures.scheme = scheme_name(c.solver.scheme);
  figures.dofs = model.global_free();
  figures.nodes = model.global_nodes();
  figures.elements = model.global_cells();
  figures.integration_points = model.total_points();
  figures.threads = omp_get_max_threads();
  figures.ranks = par::size();
  figures.linear_solver = solver->stats();
  figures.blas_kernels = blas_kernels().chosen;  // OpenBLAS's, after any restart
  figures.warnings = log.warnings();
  figures.mesh_seconds = l.mesh_seconds;
  figures.setup_seconds = l.setup_seconds;
  figures.timings = timings;
  if (heat) figures.heat = RunFigures::Heat{heat->steps(), heat->iterations(), heat->stats()};
  figures.total_seconds = since(t_start);
  finish_results(*writer, figures, log);
  log.info("{} in {:.2f} s ({} steps, {} iterations); results in {}",
           status == 0   ? "converged"
           : status == 4 ? "interrupted"
                         : "stopped",
           since(t_start), result.steps, result.iterations, dir.string());
  // --quiet drops the progress lines, not the reason a run stopped (exit status 2 alone left
  // the user to find it in hencky.log).
  if (quiet && status != 0)
    std::fprintf(stderr, "stopped: %s; the converged steps are in %s\n", result.failure.c_str(),
                 dir.string().c_str());
  return status;
}

/// hencky plot: the curves of a run's history.csv, drawn by scripts/plot_history.py with
/// Debian's python3 and matplotlib (a plotting library, not pixels of ours). The script is the
/// source tree's (HENCKY_SCRIPTS_DIR, where the binary was built) or share/hencky beside an
/// installed binary. Replaces this process with the script's; returns only on failure.
int plot(const std::vector<std::string>& args) {
  std::vector<fs::path> candidates;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share/hencky/plot_history.py");
  candidates.push_back(fs::path(HENCKY_SCRIPTS_DIR) / "plot_history.py");
  const auto script = std::find_if(candidates.begin(), candidates.end(),
                                   [](const fs::path& p) { return fs::exists(p); });
  if (script == candidates.end()) {
    std::cerr << "error: hencky plot: its script plot_history.py is neither in "
              << candidates.front().parent_path().string() << " nor in " << HENCKY_SCRIPTS_DIR
              << "\n";
    return 1;
  }
  const char* python = "/usr/bin/python3";
  std::vector<std::string> words = {python, script->string()};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  execv(python, argv.data());
  std::cerr << "error: hencky plot: cannot run " << python << " (" << std::strerror(errno)
            << "): run scripts/setup.sh, which installs python3 and python3-matplotlib\n";
  return 1;
}

int check(const std::string& case_path) {
  Log log;
  LoadedCase l = load_case(case_path, log);
  const Model& m = *l.model;
  if (!par::root()) return 0;  // under mpirun every rank checks, one reports
  std::cout << fmt::format("{}: ok\n  mesh: {}\n  unknowns: {}\n  steps: {}\n", case_path,
                           describe_mesh(m.mesh()), m.dofs().n_free, l.spec->solver.times.size());
  std::cout << "  regions:";
  for (const auto& r : m.mesh().regions) std::cout << fmt::format(" {} ({}D)", r.name, r.dim);
  std::cout << "\n";
  for (const auto& line : describe_contact(m)) std::cout << "  " << line << "\n";
  return 0;
}

/// The OpenMP threads: --threads when given (false, with the message printed, when it is
/// below 1), else OMP_NUM_THREADS or every core. More threads than the hardware runs only cost,
/// and a huge count exhausts the process's threads inside the first parallel loop: both are
/// lowered to the hardware threads, with `warning` saying so.
bool set_threads(bool given, int threads, std::string& warning) {
  const int hardware = omp_get_num_procs();
  if (given) {
    if (threads < 1) {
      std::cerr << fmt::format("error: '--threads': expected a number of threads >= 1, found {}\n",
                               threads);
      return false;
    }
    if (threads > hardware) {
      warning =
          fmt::format("--threads {} is more than the {} hardware threads of this machine: using {}",
                      threads, hardware, hardware);
      threads = hardware;
    }
    omp_set_num_threads(threads);
  } else if (std::getenv("OMP_NUM_THREADS") && omp_get_max_threads() > hardware) {
    // OMP_NUM_THREADS asks for more: the same clamp (it holds for `check` too, which meshes).
    warning = fmt::format(
        "OMP_NUM_THREADS={} is more than the {} hardware threads of this machine: using {}",
        omp_get_max_threads(), hardware, hardware);
    omp_set_num_threads(hardware);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  // First of all: it may start the process again (before any other work is done).
  restart_with_better_blas_kernels(argv);
  CLI::App app{"hencky: thermo-elastic finite-element analysis of 3D structures"};
  app.set_version_flag("--version", std::string("hencky ") + HENCKY_VERSION);
  app.require_subcommand(1);
  std::string case_path, out_dir;
  bool quiet = false;
  int threads = 0;
  auto* run_cmd = app.add_subcommand("run", "run the analysis of a case file");
  run_cmd->add_option("case", case_path, "case file (YAML)")->required();
  auto* out_opt = run_cmd->add_option("-o,--output", out_dir,
                                      "output directory (default: output.dir of the case)");
  auto* threads_opt = run_cmd->add_option(
      "--threads", threads,
      "threads for assembly (default: all cores; at most the hardware threads)");
  run_cmd->add_flag("--quiet", quiet, "no progress lines on the terminal");
  std::string restart;
  double from_time = 0;
  run_cmd->add_option("--restart", restart,
                      "continue the run whose output directory DIR holds checkpoints, from its "
                      "newest one (or --from T); the outputs continue DIR's");
  auto* from_opt = run_cmd->add_option("--from", from_time,
                                       "with --restart: the time of the checkpoint to continue "
                                       "from (default: the newest)");
  // PETSc options go in one argument: PETSc's own option names (-o..., -h...) would otherwise
  // be read as hencky's short options.
  std::vector<std::string> petsc_args;
  run_cmd->add_option("--petsc", petsc_args,
                      "PETSc options for the PETSc back end, in one quoted argument, e.g. "
                      "--petsc \"-pc_type hypre -ksp_monitor\"; they override "
                      "solver.petsc_options (the environment variable PETSC_OPTIONS also works)");
  auto* check_cmd =
      app.add_subcommand("check", "read and validate a case and its mesh, solve nothing");
  check_cmd->add_option("case", case_path, "case file (YAML)")->required();
  auto* plot_cmd = app.add_subcommand(
      "plot", "curves of a run's history.csv as DIR/plot.png and DIR/plot.svg (matplotlib)");
  std::string plot_dir, plot_x, plot_out;
  std::vector<std::string> plot_y;
  bool plot_log = false;
  plot_cmd->add_option("dir", plot_dir, "a run's output directory (holds history.csv)")->required();
  plot_cmd->add_option("--x", plot_x, "the column along x (default: time)");
  plot_cmd->add_option("--y", plot_y,
                       "columns along y, or shell patterns such as 'reaction.*.z' (default: "
                       "reactions, contact forces, probes' von Mises stress and displacement)");
  plot_cmd->add_flag("--log-y", plot_log, "logarithmic y axes (the residual, say)");
  plot_cmd->add_option("-o,--output", plot_out, "PREFIX of PREFIX.png and PREFIX.svg");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 1;
  }
  if (plot_cmd->parsed()) {
    std::vector<std::string> args = {plot_dir};
    if (!plot_x.empty()) args.insert(args.end(), {"--x", plot_x});
    if (!plot_y.empty()) {
      args.push_back("--y");
      args.insert(args.end(), plot_y.begin(), plot_y.end());
    }
    if (plot_log) args.push_back("--log-y");
    if (!plot_out.empty()) args.insert(args.end(), {"-o", plot_out});
    return plot(args);
  }
  if (from_opt->count() > 0 && restart.empty()) {
    std::cerr << "error: '--from': a checkpoint's time goes with --restart DIR\n";
    return 1;
  }
  if (out_opt->count() > 0 && out_dir.empty()) {
    std::cerr << "error: '-o': expected an output directory, found an empty path\n";
    return 1;
  }
  // Before any OpenMP region.
  std::string threads_warning;
  if (!set_threads(threads_opt->count() > 0, threads, threads_warning)) return 1;
  std::string petsc_options;
  for (const auto& a : petsc_args) petsc_options += (petsc_options.empty() ? "" : " ") + a;
  // Under mpirun every rank starts MPI and PETSc here; a serial run starts them only if its
  // case asks for the PETSc back end.
  if (par::launched_by_mpirun()) par::start(&argc, &argv);
  int status = 0;
  try {
    std::optional<double> from;
    if (from_opt->count() > 0) from = from_time;
    status = run_cmd->parsed()
                 ? run(case_path, out_dir, quiet, petsc_options, threads_warning, restart, from)
                 : check(case_path);
  } catch (const InputError& e) {
    // Errors of the analysis reach every rank alike (its decisions are collective).
    if (par::root()) std::cerr << "error: " << e.what() << "\n";
    status = 1;
  } catch (const std::exception& e) {
    if (par::size() > 1) {
      // Only this rank may have failed: the others wait in a collective call. Stop them all.
      std::cerr << fmt::format("rank {}: internal error: {}\n", par::rank(), e.what());
      par::abort_all(3);
    }
    std::cerr << "internal error: " << e.what() << "\n";
    status = 3;
  }
  par::finish();
  return status;
}
