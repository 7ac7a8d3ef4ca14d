#include "parallel/mesh_part.hpp"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstring>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/packed_bytes.hpp"
#include "fem/reference_element.hpp"
#include "parallel/mpi.hpp"
#include "parallel/shared_nodes.hpp"

namespace hencky {

MeshPart extract_part(const Mesh& whole, const Partition& partition) {
  const int rank = partition.rank, n_whole = whole.n_nodes();
  if (static_cast<int>(partition.cell_owner.size()) != whole.cells.size() ||
      static_cast<int>(partition.node_owner.size()) != n_whole)
    throw std::invalid_argument("extract_part: the partition is not one of this mesh");
  MeshPart part;
  // Each node's index among its owner's own nodes (the whole mesh's order).
  std::vector<int> index_at_owner(n_whole), counter(partition.parts, 0);
  for (int n = 0; n < n_whole; ++n) index_at_owner[n] = counter[partition.node_owner[n]]++;

  // The nodes of the rank's cells: owned ones first, then the ghosts, each in global order.
  std::vector<char> touched(n_whole, 0);
  for (int c = 0; c < whole.cells.size(); ++c)
    if (partition.cell_owner[c] == rank)
      for (int n : whole.cells.nodes(c)) touched[n] = 1;
  // A node of no cell (a stray node) is owned by rank 0 (partition_from): it is in rank 0's part.
  for (int n = 0; n < n_whole; ++n)
    if (partition.node_owner[n] == rank) touched[n] = 1;
  std::vector<int> local(n_whole, -1);
  for (int pass = 0; pass < 2; ++pass)
    for (int n = 0; n < n_whole; ++n)
      if (touched[n] && (partition.node_owner[n] == rank) == (pass == 0)) {
        local[n] = static_cast<int>(part.global_node.size());
        part.global_node.push_back(n);
      }
  part.owned_nodes = counter[rank];
  Mesh& m = part.mesh;
  for (int n : part.global_node) {
    m.x.push_back(whole.x[n]);
    m.node_tag.push_back(whole.node_tag[n]);
    part.node_owner.push_back(partition.node_owner[n]);
    part.owner_index.push_back(index_at_owner[n]);
  }

  std::vector<int> local_cell(whole.cells.size(), -1);
  std::vector<int> conn;
  long long point = 0;  // the whole mesh's points before cell c
  for (int c = 0; c < whole.cells.size(); ++c) {
    const long long first = point;
    point += reference_table(whole.cells.type[c]).n_points;
    if (partition.cell_owner[c] != rank) continue;
    part.global_point.push_back(first);
    conn.clear();
    for (int n : whole.cells.nodes(c)) conn.push_back(local[n]);
    local_cell[c] = m.cells.size();
    m.cells.add(whole.cells.type[c], conn, whole.cells.tag[c]);
    m.cell_region.push_back(whole.cell_region.empty() ? -1 : whole.cell_region[c]);
    part.global_cell.push_back(c);
  }

  // Faces: those whose corners all lie in one of the rank's cells. The local cells at each
  // local node (CSR) find them.
  const int n_local = static_cast<int>(part.global_node.size());
  std::vector<int> at_ptr(n_local + 1, 0), at_cell;
  for (int c = 0; c < m.cells.size(); ++c)
    for (int n : m.cells.nodes(c)) ++at_ptr[n + 1];
  for (int n = 0; n < n_local; ++n) at_ptr[n + 1] += at_ptr[n];
  at_cell.resize(at_ptr.back());
  {
    std::vector<int> fill(at_ptr.begin(), at_ptr.end() - 1);
    for (int c = 0; c < m.cells.size(); ++c)
      for (int n : m.cells.nodes(c)) at_cell[fill[n]++] = c;
  }
  std::vector<int> local_face(whole.faces.size(), -1);
  for (int f = 0; f < whole.faces.size(); ++f) {
    const auto nodes = whole.faces.nodes(f);
    conn.clear();
    for (int n : nodes) conn.push_back(local[n]);
    if (std::find(conn.begin(), conn.end(), -1) != conn.end()) continue;
    const int corners = cell_n_corners(whole.faces.type[f]);
    bool on_a_cell = false;
    for (int k = at_ptr[conn[0]]; k < at_ptr[conn[0] + 1] && !on_a_cell; ++k) {
      const auto cn = m.cells.nodes(at_cell[k]);
      on_a_cell = true;
      for (int a = 1; a < corners && on_a_cell; ++a)
        on_a_cell = std::find(cn.begin(), cn.end(), conn[a]) != cn.end();
    }
    if (!on_a_cell) continue;
    local_face[f] = m.faces.size();
    m.faces.add(whole.faces.type[f], conn, whole.faces.tag[f]);
    part.global_face.push_back(f);
  }

  for (const Region& r : whole.regions) {
    Region& p = m.regions.emplace_back();
    p.name = r.name;
    p.dim = r.dim;
    const std::vector<int>& to_local = r.dim == 3 ? local_cell : local_face;
    for (int e : r.cells)
      if (to_local[e] >= 0) p.cells.push_back(to_local[e]);
    for (int n : r.nodes)
      if (local[n] >= 0) p.nodes.push_back(local[n]);
    std::sort(p.nodes.begin(), p.nodes.end());
  }
  return part;
}

namespace {

void put_cells(ByteWriter& w, const CellSet& c) {
  w.vector(c.type);
  w.vector(c.offset);
  w.vector(c.conn);
  w.vector(c.tag);
}
void get_cells(ByteReader& r, CellSet& c) {
  r.vector(c.type);
  r.vector(c.offset);
  r.vector(c.conn);
  r.vector(c.tag);
}

constexpr std::uint64_t part_magic = 0x6865'6e63'6b79'7032;  // "hencky" part, version 2

}  // namespace

std::string pack(const MeshPart& part) {
  ByteWriter w;
  w.value(part_magic);
  const Mesh& m = part.mesh;
  w.vector(m.x);
  w.vector(m.node_tag);
  put_cells(w, m.cells);
  w.vector(m.cell_region);
  put_cells(w, m.faces);
  w.value(static_cast<std::uint64_t>(m.regions.size()));
  for (const Region& r : m.regions) {
    w.string(r.name);
    w.value(r.dim);
    w.vector(r.cells);
    w.vector(r.nodes);
  }
  w.value(part.owned_nodes);
  w.vector(part.global_node);
  w.vector(part.node_owner);
  w.vector(part.owner_index);
  w.vector(part.global_cell);
  w.vector(part.global_point);
  w.vector(part.global_face);
  return w.take();
}

MeshPart unpack(std::string_view bytes) {
  ByteReader r(bytes, "not a packed mesh part");
  std::uint64_t magic = 0;
  r.value(magic);
  if (magic != part_magic) throw std::invalid_argument("not a packed mesh part");
  MeshPart part;
  Mesh& m = part.mesh;
  r.vector(m.x);
  r.vector(m.node_tag);
  get_cells(r, m.cells);
  r.vector(m.cell_region);
  get_cells(r, m.faces);
  std::uint64_t n_regions = 0;
  r.value(n_regions);
  if (n_regions > bytes.size()) throw std::invalid_argument("not a packed mesh part");
  m.regions.resize(n_regions);
  for (Region& g : m.regions) {
    r.string(g.name);
    r.value(g.dim);
    r.vector(g.cells);
    r.vector(g.nodes);
  }
  r.value(part.owned_nodes);
  r.vector(part.global_node);
  r.vector(part.node_owner);
  r.vector(part.owner_index);
  r.vector(part.global_cell);
  r.vector(part.global_point);
  r.vector(part.global_face);
  if (!r.done()) throw std::invalid_argument("not a packed mesh part");
  return part;
}

MeshPart scatter_parts(const Mesh* whole, const std::vector<int>& cell_owner) {
  const int ranks = par::size();
  if (!par::root()) return unpack(par::receive_bytes(0));
  if (!whole) throw std::invalid_argument("scatter_parts: root has no mesh");
  // The node owners once; each rank's part in turn, sent and freed.
  Partition p = partition_from(*whole, cell_owner, ranks, 0);
  for (int r = 1; r < ranks; ++r) {
    p.rank = r;
    par::send_bytes(r, pack(extract_part(*whole, p)));
  }
  p.rank = 0;
  return extract_part(*whole, p);
}

namespace {

/// `cells` with its nodes renumbered by `local`.
CellSet renumbered(const CellSet& cells, const std::vector<int>& local) {
  CellSet out;
  std::vector<int> conn;
  for (int c = 0; c < cells.size(); ++c) {
    conn.clear();
    for (int n : cells.nodes(c)) conn.push_back(local[n]);
    out.add(cells.type[c], conn, cells.tag[c]);
  }
  return out;
}

}  // namespace

MeshPart part_of_piece(Mesh piece) {
  const int n = piece.n_nodes(), me = par::rank();
  const SharedNodes s =
      share_nodes(std::vector<long long>(piece.node_tag.begin(), piece.node_tag.end()));
  if (par::any(s.total > INT_MAX))
    throw std::invalid_argument("part_of_piece: more nodes than an int counts");
  // Owned nodes first, in the piece's order (that of their whole numbers), then the ghosts by
  // their whole numbers.
  std::vector<int> order;
  order.reserve(n);
  for (int i = 0; i < n; ++i)
    if (s.owner[i] == me) order.push_back(i);
  const auto ghosts = order.size();
  for (int i = 0; i < n; ++i)
    if (s.owner[i] != me) order.push_back(i);
  std::sort(order.begin() + static_cast<std::ptrdiff_t>(ghosts), order.end(),
            [&](int a, int b) { return s.global[a] < s.global[b]; });
  std::vector<int> local(n);
  for (int k = 0; k < n; ++k) local[order[k]] = k;

  MeshPart part;
  Mesh& m = part.mesh;
  part.owned_nodes = s.owned;
  for (int old : order) {
    m.x.push_back(piece.x[old]);
    m.node_tag.push_back(piece.node_tag[old]);
    part.global_node.push_back(static_cast<int>(s.global[old]));
    part.node_owner.push_back(s.owner[old]);
    part.owner_index.push_back(s.owner_index[old]);
  }
  m.cells = renumbered(piece.cells, local);
  m.faces = renumbered(piece.faces, local);
  // Every part has every region of the whole mesh (an empty one where it holds none of it): the
  // union of the pieces' regions, by dimension and name.
  std::string names;
  for (const Region& r : piece.regions) names += std::to_string(r.dim) + " " + r.name + "\n";
  std::string all;
  if (par::root()) {
    std::set<std::pair<int, std::string>> regions;
    for (const std::string& text : par::gather_strings(names)) {
      std::istringstream in(text);
      int dim = 0;
      std::string name;
      while (in >> dim && in.get() == ' ' && std::getline(in, name)) regions.insert({dim, name});
    }
    for (const auto& [dim, name] : regions) all += std::to_string(dim) + " " + name + "\n";
  } else {
    par::gather_strings(names);
  }
  par::broadcast(all);
  std::vector<int> new_index(piece.regions.size(), -1);
  {
    std::istringstream in(all);
    int dim = 0;
    std::string name;
    while (in >> dim && in.get() == ' ' && std::getline(in, name)) {
      Region& r = m.regions.emplace_back();
      r.dim = dim;
      r.name = name;
      for (std::size_t k = 0; k < piece.regions.size(); ++k)
        if (piece.regions[k].dim == dim && piece.regions[k].name == name) {
          new_index[k] = static_cast<int>(m.regions.size()) - 1;
          r.cells = std::move(piece.regions[k].cells);
          r.nodes = std::move(piece.regions[k].nodes);
        }
      for (int& v : r.nodes) v = local[v];
      std::sort(r.nodes.begin(), r.nodes.end());
    }
  }
  m.cell_region = std::move(piece.cell_region);
  for (int& r : m.cell_region)
    if (r >= 0) r = new_index.at(r);
  const long long first_cell = par::rank_offsets(m.cells.size())[me],
                  first_face = par::rank_offsets(m.faces.size())[me];
  long long points = 0;
  for (int c = 0; c < m.cells.size(); ++c) {
    part.global_cell.push_back(static_cast<int>(first_cell + c));
    part.global_point.push_back(points);
    points += reference_table(m.cells.type[c]).n_points;
  }
  const long long first_point = par::rank_offsets(points)[me];
  for (long long& p : part.global_point) p += first_point;
  for (int f = 0; f < m.faces.size(); ++f)
    part.global_face.push_back(static_cast<int>(first_face + f));
  return part;
}

}  // namespace hencky
