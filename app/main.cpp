// hencky: command line (see docs/cli.md and the contract CASE_FORMAT.md).
// Exit status: 0 converged, 1 bad input, 2 a step did not converge, 3 internal error,
// 4 interrupted (SIGINT or SIGTERM; the converged steps and a checkpoint are kept), 130 a second
// SIGINT stopped the run at once.
// Here the command line is parsed, and `check` and `plot` run; `run` is app/run.cpp's, which loads
// the model on the ranks with app/load.cpp.
#include <fmt/format.h>
#include <omp.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>

#include "core/log.hpp"
#include "hencky/version.hpp"
#include "input/gmsh_child.hpp"
#include "input/gmsh_reader.hpp"
#include "input/inp_reader.hpp"
#include "input/load_case.hpp"
#include "linalg/blas_kernels.hpp"
#include "parallel/mpi.hpp"
#include "run.hpp"
#include "solve/driver.hpp"

namespace {
using namespace hencky;
namespace fs = std::filesystem;

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
                           describe_mesh(m.mesh()),
                           m.spec().heat.only ? fmt::format("{} temperatures", m.mesh().n_nodes())
                                              : std::to_string(m.dofs().n_free),
                           l.spec->solver.times.size());
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

/// `hencky ccx -i JOB`: the deck JOB.inp (JOB may name it with its extension too).
std::string ccx_deck(const std::string& job) {
  return is_inp_file(job) ? job : job + ".inp";
}

/// `hencky ccx -i JOB`: JOB.dat and JOB.frd beside the deck, where ccx writes them, copied from
/// the run's output directory JOB.out (a front end that calls ccx reads them there). One the run
/// did not write (a run on several MPI ranks writes neither) is removed beside the deck: a front
/// end must not read an earlier run's as this one's.
void copy_ccx_files(const std::string& deck) {
  const fs::path inp(deck), out = fs::path(deck).replace_extension(".out");
  for (const char* ext : {".dat", ".frd"}) {
    const fs::path from = out / fs::path(inp.filename()).replace_extension(ext);
    const fs::path to = fs::path(inp).replace_extension(ext);
    std::error_code ec;
    if (fs::exists(from, ec))
      fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
    else if (fs::exists(to, ec) && fs::remove(to, ec))
      std::cerr << "warning: " << to.string()
                << " of an earlier run removed: this run wrote none\n";
    if (ec)
      std::cerr << "warning: cannot copy " << from.string() << " to " << to.string() << ": "
                << ec.message() << "\n";
  }
}

/// The command line's words, as CLI11 fills them.
struct Words {
  CLI::App* run_cmd = nullptr;
  CLI::App* plot_cmd = nullptr;
  CLI::App* ccx_cmd = nullptr;
  std::string ccx_job;
  CLI::Option *out_opt = nullptr, *threads_opt = nullptr, *from_opt = nullptr;
  std::string case_path, out_dir;
  bool quiet = false;
  int threads = 0;
  std::string restart;
  double from_time = 0;
  std::vector<std::string> petsc_args;
  std::string plot_dir, plot_x, plot_out;
  std::vector<std::string> plot_y;
  bool plot_log = false;
};

/// The subcommands run, check and plot, their arguments and options, filling `w`.
void define_commands(CLI::App& app, Words& w) {
  app.set_version_flag("--version", std::string("hencky ") + HENCKY_VERSION);
  app.require_subcommand(1);
  w.run_cmd = app.add_subcommand("run", "run the analysis of a case file");
  w.run_cmd->add_option("case", w.case_path, "case file (YAML)")->required();
  w.out_opt = w.run_cmd->add_option("-o,--output", w.out_dir,
                                    "output directory (default: output.dir of the case)");
  w.threads_opt = w.run_cmd->add_option(
      "--threads", w.threads,
      "threads for assembly (default: all cores; at most the hardware threads)");
  w.run_cmd->add_flag("--quiet", w.quiet, "no progress lines on the terminal");
  w.run_cmd->add_option("--restart", w.restart,
                        "continue the run whose output directory DIR holds checkpoints, from its "
                        "newest one (or --from T); the outputs continue DIR's");
  w.from_opt = w.run_cmd->add_option("--from", w.from_time,
                                     "with --restart: the time of the checkpoint to continue "
                                     "from (default: the newest)");
  // PETSc options go in one argument: PETSc's own option names (-o..., -h...) would otherwise
  // be read as hencky's short options.
  w.run_cmd->add_option("--petsc", w.petsc_args,
                        "PETSc options for the PETSc back end, in one quoted argument, e.g. "
                        "--petsc \"-pc_type hypre -ksp_monitor\"; they override "
                        "solver.petsc_options (the environment variable PETSC_OPTIONS also works)");
  auto* check_cmd =
      app.add_subcommand("check", "read and validate a case and its mesh, solve nothing");
  check_cmd->add_option("case", w.case_path, "case file (YAML)")->required();
  w.ccx_cmd = app.add_subcommand(
      "ccx", "run JOB.inp as ccx would be called on it: JOB.dat and JOB.frd beside it");
  w.ccx_cmd->add_option("-i", w.ccx_job, "the job: its deck is JOB.inp")->required();
  w.ccx_cmd->add_flag("--quiet", w.quiet, "no progress lines on the terminal");
  w.plot_cmd = app.add_subcommand(
      "plot", "curves of a run's history.csv as DIR/plot.png and DIR/plot.svg (matplotlib)");
  w.plot_cmd->add_option("dir", w.plot_dir, "a run's output directory (holds history.csv)")
      ->required();
  w.plot_cmd->add_option("--x", w.plot_x, "the column along x (default: time)");
  w.plot_cmd->add_option("--y", w.plot_y,
                         "columns along y, or shell patterns such as 'reaction.*.z' (default: "
                         "reactions, contact forces, probes' von Mises stress and displacement)");
  w.plot_cmd->add_flag("--log-y", w.plot_log, "logarithmic y axes (the residual, say)");
  w.plot_cmd->add_option("-o,--output", w.plot_out, "PREFIX of PREFIX.png and PREFIX.svg");
}

/// plot_history.py's arguments of `hencky plot`'s.
std::vector<std::string> plot_arguments(const Words& w) {
  std::vector<std::string> args = {w.plot_dir};
  if (!w.plot_x.empty()) args.insert(args.end(), {"--x", w.plot_x});
  if (!w.plot_y.empty()) {
    args.push_back("--y");
    args.insert(args.end(), w.plot_y.begin(), w.plot_y.end());
  }
  if (w.plot_log) args.push_back("--log-y");
  if (!w.plot_out.empty()) args.insert(args.end(), {"-o", w.plot_out});
  return args;
}

}  // namespace

int main(int argc, char** argv) {
  // Gmsh's work runs in a child process, which is this program started with gmsh_child::marker
  // (input/gmsh_child.hpp): a crash inside Gmsh is then an input error, not the end of the run.
  run_gmsh_in_child_processes();
  if (argc > 1 && std::strcmp(argv[1], gmsh_child::marker) == 0)
    return gmsh_child::child_main(argc, argv);
  // First of all: it may start the process again (before any other work is done).
  restart_with_better_blas_kernels(argv);
  CLI::App app{"hencky: thermo-elastic finite-element analysis of 3D structures"};
  Words w;
  define_commands(app, w);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 1;
  }
  if (w.plot_cmd->parsed()) return plot(plot_arguments(w));
  if (w.from_opt->count() > 0 && w.restart.empty()) {
    std::cerr << "error: '--from': a checkpoint's time goes with --restart DIR\n";
    return 1;
  }
  if (w.out_opt->count() > 0 && w.out_dir.empty()) {
    std::cerr << "error: '-o': expected an output directory, found an empty path\n";
    return 1;
  }
  if (w.ccx_cmd->parsed()) w.case_path = ccx_deck(w.ccx_job);
  cli::RunRequest request{w.case_path, w.out_dir, w.quiet, "", "", w.restart, std::nullopt};
  // Before any OpenMP region.
  if (!set_threads(w.threads_opt->count() > 0, w.threads, request.threads_warning)) return 1;
  for (const auto& a : w.petsc_args)
    request.petsc_options += (request.petsc_options.empty() ? "" : " ") + a;
  if (w.from_opt->count() > 0) request.from = w.from_time;
  // Under mpirun every rank starts MPI and PETSc here; a serial run starts them only if its
  // case asks for the PETSc back end.
  if (par::launched_by_mpirun()) par::start(&argc, &argv);
  int status = 0;
  try {
    status = w.run_cmd->parsed() || w.ccx_cmd->parsed() ? cli::run(request) : check(w.case_path);
    if (w.ccx_cmd->parsed() && (status == 0 || status == 2) && par::root())
      copy_ccx_files(w.case_path);
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
