// The ghost exchange of a distributed mesh (parallel/node_exchange.hpp), and the parts sent from
// root (scatter_parts). Run as part of the unit tests on one process, and on 3 MPI ranks by
// ctest's mpi_node_exchange (mpirun -np 3 hencky_tests
// --gtest_filter='NodeExchange.*:PartScatter.*'): every rank reads the same box, takes its part
// under the same METIS split, and exchanges. The sums are checked against the whole mesh: a
// vector "assembled" from each rank's cells (1 for every cell at a node) must give every copy
// of a node the number of cells around it in the whole mesh.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "input/gmsh_reader.hpp"
#include "mesh_part_support.hpp"
#include "parallel/mpi.hpp"
#include "parallel/node_exchange.hpp"
#include "parallel/shared_nodes.hpp"
#include "verify_support.hpp"

namespace fs = std::filesystem;
using namespace hencky;
using namespace hencky::verify;

namespace {

struct Distributed {
  Mesh whole;
  MeshPart part;
};

Distributed distributed_box() {
  par::ensure_petsc();
  TempDir dir("node_exchange");
  write_file(dir / "box.geo", box_geo(2, 1, 1, 0.25));
  MeshReadOptions opt;
  opt.order = 2;
  Distributed d;
  d.whole = read_gmsh(dir / "box.geo", opt);
  const int ranks = par::size();
  d.part = extract_part(d.whole,
                        partition_from(d.whole, split_cells(d.whole, ranks), ranks, par::rank()));
  return d;
}

/// A value of global node g, component k.
double value_of(int g, int k) {
  return 1000.0 * g + k + 0.25;
}

TEST(NodeExchange, GhostsTakeTheirOwnersValues) {
  const Distributed d = distributed_box();
  const MeshPart& p = d.part;
  const NodeExchange exchange(p);
  const int n = p.mesh.n_nodes();
  EXPECT_EQ(exchange.local_nodes(), n);
  EXPECT_EQ(exchange.owned_nodes(), p.owned_nodes);
  if (par::size() > 1) {
    EXPECT_GT(par::sum(static_cast<long long>(n - p.owned_nodes)), 0);  // there are ghosts
  }
  for (int width : {1, 3}) {
    std::vector<double> v(static_cast<std::size_t>(width) * n,
                          std::numeric_limits<double>::quiet_NaN());
    for (int i = 0; i < p.owned_nodes; ++i)
      for (int k = 0; k < width; ++k) v[width * i + k] = value_of(p.global_node[i], k);
    exchange.to_ghosts(v, width);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < width; ++k)
        ASSERT_EQ(v[width * i + k], value_of(p.global_node[i], k))
            << "rank " << par::rank() << " local node " << i << " of " << n;
  }
}

TEST(NodeExchange, SumsGiveEveryCopyTheWholeMeshsTotal) {
  const Distributed d = distributed_box();
  const MeshPart& p = d.part;
  const NodeExchange exchange(p);
  const int n = p.mesh.n_nodes();
  std::vector<int> cells_at(d.whole.n_nodes(), 0);
  for (int c = 0; c < d.whole.cells.size(); ++c)
    for (int g : d.whole.cells.nodes(c)) ++cells_at[g];
  // Width 2: the count, and the count times a node's own number (so that a value summed
  // into the wrong node shows).
  std::vector<double> v(2 * static_cast<std::size_t>(n), 0.0);
  for (int c = 0; c < p.mesh.cells.size(); ++c)
    for (int i : p.mesh.cells.nodes(c)) {
      v[2 * i] += 1;
      v[2 * i + 1] += p.global_node[i];
    }
  exchange.sum(v, 2);
  for (int i = 0; i < n; ++i) {
    const int g = p.global_node[i];
    ASSERT_EQ(v[2 * i], cells_at[g]) << "rank " << par::rank() << " node " << g;
    ASSERT_EQ(v[2 * i + 1], static_cast<double>(cells_at[g]) * g);
  }
}

// Root reads the mesh and sends each rank its part; every rank gets what it would extract from
// the whole mesh itself.
TEST(PartScatter, EveryRankReceivesItsPart) {
  const Distributed d = distributed_box();
  const int ranks = par::size();
  const std::vector<int> owner = split_cells(d.whole, ranks);
  const MeshPart received =
      scatter_parts(par::root() ? &d.whole : nullptr, par::root() ? owner : std::vector<int>());
  EXPECT_TRUE(same_part(received, d.part)) << "rank " << par::rank();
  EXPECT_EQ(par::sum(static_cast<long long>(received.mesh.cells.size())), d.whole.cells.size());
}

TEST(NodeExchange, AWrongLengthIsRefused) {
  const Distributed d = distributed_box();
  const NodeExchange exchange(d.part);
  std::vector<double> v(3 * d.part.mesh.n_nodes() + 1);
  EXPECT_THROW(exchange.to_ghosts(v, 3), std::invalid_argument);
  EXPECT_THROW(exchange.sum(v, 0), std::invalid_argument);
}

}  // namespace

// The owners of shared nodes found from their tags alone (share_nodes, the way in for a mesh
// whose files no rank reads whole): on the parts of a METIS split they are the parts' own
// owners (the lowest rank whose cells touch the node), with the same index at the owner, and
// the whole numbering counts every node once. The tags go in shuffled: a rank's own nodes are
// numbered in the order given, and a ghost learns its owner's number.
TEST(SharedNodes, OwnersFromTagsAreThePartitionsOwners) {
  const Distributed d = distributed_box();
  const MeshPart& p = d.part;
  const int n = p.mesh.n_nodes();
  std::vector<long long> tags(p.mesh.node_tag.begin(), p.mesh.node_tag.end());
  const SharedNodes s = share_nodes(tags);
  ASSERT_EQ(static_cast<int>(s.owner.size()), n);
  EXPECT_EQ(s.owned, p.owned_nodes);
  EXPECT_EQ(s.total, d.whole.n_nodes());
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(s.owner[i], p.node_owner[i]) << "node " << tags[i];
    EXPECT_EQ(s.owner_index[i], p.owner_index[i]) << "node " << tags[i];
  }
  // Reversed: the owned nodes are numbered in the new order, and every copy agrees.
  {
    std::vector<int> order(n);
    for (int i = 0; i < n; ++i) order[i] = n - 1 - i;
    std::vector<long long> shuffled(n);
    for (int i = 0; i < n; ++i) shuffled[i] = tags[order[i]];
    const SharedNodes r = share_nodes(shuffled);
    // Root checks that each tag has one number over all ranks, and the numbers are 0 .. N-1.
    std::string mine;
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(r.owner[i], s.owner[order[i]]);
      mine += std::to_string(shuffled[i]) + " " + std::to_string(r.global[i]) + "\n";
    }
    const auto all = par::gather_strings(mine);
    if (par::root()) {
      std::map<long long, long long> number;
      std::set<long long> used;
      for (const std::string& text : all) {
        std::istringstream in(text);
        long long t = 0, g = 0;
        while (in >> t >> g) {
          const auto [it, fresh] = number.emplace(t, g);
          EXPECT_EQ(it->second, g) << "tag " << t;
          if (fresh) used.insert(g);
        }
      }
      EXPECT_EQ(static_cast<long long>(number.size()), r.total);
      EXPECT_EQ(static_cast<long long>(used.size()), r.total);
      EXPECT_EQ(*used.begin(), 0);
      EXPECT_EQ(*used.rbegin(), r.total - 1);
    }
  }
  // A tag twice on one rank is refused on every rank.
  std::vector<long long> twice = tags;
  if (par::root()) twice.push_back(tags.front());
  EXPECT_THROW(share_nodes(twice), std::invalid_argument);
}

// The second way in (part_of_piece): each rank reads its own file of a mesh that Gmsh split
// into as many files as there are ranks, and no rank reads the whole. Its part must hold what
// the whole mesh holds there: every node owned once, every cell and region face once, every
// region on every rank, and the ghost exchange must give each copy of a node the whole mesh's
// count of cells around it (found here by node tag, from the unsplit file).
TEST(SharedNodes, EachRankReadsItsFileOfASplitMesh) {
  const int ranks = par::size();
  if (ranks == 1) GTEST_SKIP() << "needs several ranks (ctest's mpi_node_exchange runs it on 3)";
  par::ensure_petsc();
  TempDir dir("split_mesh");
  write_file(dir / "box.geo", box_geo(2, 1, 1, 0.25));
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::open((dir / "box.geo").string());
  gmsh::model::mesh::generate(3);
  gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 1);
  gmsh::model::mesh::setOrder(2);
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::option::setNumber("Mesh.Binary", 1);
  gmsh::write((dir / "whole.msh").string());
  gmsh::model::mesh::partition(ranks);
  gmsh::option::setNumber("Mesh.PartitionSplitMeshFiles", 1);
  gmsh::write((dir / "split.msh").string());
  gmsh::finalize();

  const Mesh whole = read_gmsh(dir / "whole.msh", {});
  MeshReadOptions piece;
  piece.piece = true;
  const fs::path mine = dir / ("split_" + std::to_string(par::rank() + 1) + ".msh");
  const MeshPart p = part_of_piece(read_gmsh(mine, piece));
  const Mesh& m = p.mesh;
  EXPECT_EQ(par::sum(static_cast<long long>(p.owned_nodes)), whole.n_nodes());
  EXPECT_EQ(par::sum(static_cast<long long>(m.cells.size())), whole.cells.size());
  EXPECT_EQ(par::max(p.global_cell.empty() ? -1 : p.global_cell.back()), whole.cells.size() - 1);
  // The regions: the whole mesh's on every rank, their cells and faces each on one rank.
  ASSERT_EQ(m.regions.size(), whole.regions.size());
  for (const Region& w : whole.regions) {
    const Region* r = m.find_region(w.name);
    ASSERT_NE(r, nullptr) << w.name;
    EXPECT_EQ(r->dim, w.dim);
    EXPECT_EQ(par::sum(static_cast<long long>(r->cells.size())),
              static_cast<long long>(w.cells.size()))
        << w.name;
  }
  for (int c = 0; c < m.cells.size(); ++c) ASSERT_GE(m.cell_region[c], 0);
  // Cells at each node, summed over the copies, against the whole mesh's by tag.
  std::map<long, double> around;
  for (int c = 0; c < whole.cells.size(); ++c)
    for (int n : whole.cells.nodes(c)) around[whole.node_tag[n]] += 1;
  const NodeExchange exchange(p);
  std::vector<double> count(m.n_nodes(), 0.0);
  for (int c = 0; c < m.cells.size(); ++c)
    for (int n : m.cells.nodes(c)) count[n] += 1;
  exchange.sum(count, 1);
  int ghosts = 0;
  for (int n = 0; n < m.n_nodes(); ++n) {
    EXPECT_EQ(count[n], around.at(m.node_tag[n])) << "node " << m.node_tag[n];
    ghosts += n >= p.owned_nodes;
  }
  EXPECT_GT(par::sum(static_cast<long long>(ghosts)), 0);

  // The files read together (read_pieces: one rank, other rank counts, contact) number the
  // whole mesh as the parts do, so that checkpoints pass between the ways: each local node,
  // cell and face is at its whole number there, with its tag, coordinates and nodes.
  std::vector<fs::path> files;
  for (int r = 1; r <= ranks; ++r) files.push_back(dir / ("split_" + std::to_string(r) + ".msh"));
  const Mesh together = read_pieces(files, {});
  ASSERT_EQ(together.n_nodes(), whole.n_nodes());
  ASSERT_EQ(together.cells.size(), whole.cells.size());
  for (int n = 0; n < m.n_nodes(); ++n) {
    const int g = p.global_node[n];
    ASSERT_EQ(together.node_tag[g], m.node_tag[n]) << "local node " << n;
    EXPECT_EQ(together.x[g], m.x[n]);
  }
  for (int c = 0; c < m.cells.size(); ++c) {
    const int g = p.global_cell[c];
    ASSERT_EQ(together.cells.tag[g], m.cells.tag[c]);
    const auto a = together.cells.nodes(g), b = m.cells.nodes(c);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k], p.global_node[b[k]]);
    EXPECT_EQ(together.regions[together.cell_region[g]].name, m.regions[m.cell_region[c]].name);
  }
  for (int f = 0; f < m.faces.size(); ++f)
    EXPECT_EQ(together.faces.tag[p.global_face[f]], m.faces.tag[f]);
  // A file that is not the partition its place in the series names is refused.
  std::vector<fs::path> swapped = files;
  std::swap(swapped[0], swapped[1]);
  EXPECT_THROW(read_pieces(swapped, {}), InputError);
}
