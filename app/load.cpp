// The model of a run on its ranks (load.hpp).
#include "load.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <span>
#include <sstream>

#include "core/timer.hpp"
#include "input/gmsh_reader.hpp"
#include "output/results.hpp"
#include "parallel/mesh_part.hpp"
#include "parallel/mpi.hpp"
#include "parallel/partition.hpp"
#include "together.hpp"

namespace hencky::cli {
namespace fs = std::filesystem;
namespace {

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
    out.mesh_line = fmt::format("{}; {}", describe_mesh(m.mesh()),
                                describe_unknowns(m, m.dofs().n_free, m.mesh().n_nodes()));
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
  Log quiet;  // root's whole model has said what there is to say
  quiet.silent = true;
  if (int code = together([&] { l.model = std::make_unique<Model>(*l.spec, std::move(part), quiet); }))
    return code;
  l.model->join(quiet);
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
  MeshPart part;
  {
    ScopedTimer timer(l.mesh_seconds);  // l is fresh: its times are 0
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
    if (int code = together([&] { part = part_of_piece(std::move(piece)); })) return code;
  }
  {
    ScopedTimer timer(l.setup_seconds);
    if (int code =
            together([&] { l.model = std::make_unique<Model>(*l.spec, std::move(part), log); }))
      return code;
    if (int code = together([&] { l.model->join(log); })) return code;
  }
  const Model& m = *l.model;
  std::vector<double> of_type(static_cast<int>(CellType::quad8) + 1, 0.0);  // exact counts
  for (CellType t : m.mesh().cells.type) ++of_type[static_cast<int>(t)];
  par::sum_in_place(std::span<double>(of_type));
  std::map<std::string, long long> by_type;
  for (std::size_t t = 0; t < of_type.size(); ++t)
    if (of_type[t] > 0)
      by_type[std::string(cell_name(static_cast<CellType>(t)))] = std::llround(of_type[t]);
  out.mesh_line =
      fmt::format("{}; {}", describe_counts(m.global_nodes(), m.global_cells(), by_type),
                  describe_unknowns(m, m.global_free(), m.global_nodes()));
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
      fmt::format("{}; {}", describe_mesh(l.model->mesh()),
                  describe_unknowns(*l.model, l.model->dofs().n_free, l.model->mesh().n_nodes()));
  out.contact_lines = describe_contact(*l.model);
  return 0;
}

}  // namespace

bool distributes_mesh() {
  const char* v = std::getenv("HENCKY_REPLICATED");
  const bool replicated = v && *v && std::string(v) != "0";
  return par::size() > 1 && !replicated;
}

int load_model(std::unique_ptr<Case> spec, bool distribute, const fs::path& dir,
               const SourceLocation& dir_where, Log& log, Loaded& out) {
  // A split mesh on as many ranks as files: each rank reads its own.
  const bool own_files = distribute && spec->mesh.split && spec->mesh.pieces == par::size();
  if (distribute && spec->mesh.split && !own_files)
    out.split_line = fmt::format(
        "split mesh: root read its {} files and sent each rank its part ({} files on {} ranks)",
        spec->mesh.pieces, spec->mesh.pieces, par::size());
  return own_files    ? load_split(std::move(spec), dir, dir_where, log, out)
         : distribute ? load_distributed(std::move(spec), dir, dir_where, log, out)
                      : load_replicated(std::move(spec), dir, dir_where, log, out);
}

}  // namespace hencky::cli
