// Contact bound to the mesh: each contact's surface and points, their stiffness scale and
// starting gaps, and on a part the points bound together with the other ranks'.
#include "solve/model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tuple>
#include <unordered_map>

#include "contact/surface_type.hpp"
#include "core/invariant.hpp"
#include "fem/geometry.hpp"
#include "fem/reference_element.hpp"
#include "parallel/mpi.hpp"
#include "parallel/node_exchange.hpp"

namespace hencky {

void Model::bind_contact() {
  for (const ContactSpec& spec : case_->contact) {
    const Region& region = find_region(spec.nodes, spec.nodes_where, 2, 2, "physical surface");
    ContactBody body;
    body.spec = &spec;
    body.surface = surface_type(spec.surface.type).make(spec.surface);
    // A part's points are bound in join(): their areas, element sizes and stiffness sum
    // over the ranks that hold faces and cells at them.
    if (dist_.part) {
      contacts_.push_back(std::move(body));
      continue;
    }
    body.points = contact_points(mesh_, region, spec.nodes_where);
    add_contact_stiffness(body.points);
    const std::string error = start_contact(body, nullptr);
    if (!error.empty()) throw InputError(spec.surface.where, error);
    contacts_.push_back(std::move(body));
  }
}

void Model::add_contact_stiffness(std::vector<ContactPoint>& points) const {
  // Stiffness scale of each point for κ = auto: tr(K_aa)/3 of the elastic matrix at T_ref,
  // Σ over the cells at the node of ∫ (λ + 4μ)/3 |∇N_a|² dV.
  std::vector<int> node_point(mesh_.n_nodes(), -1);
  for (std::size_t i = 0; i < points.size(); ++i) node_point[points[i].node] = static_cast<int>(i);
  CellKinematics kin;
  Vec3 x[max_cell_nodes];
  for (int e = 0; e < mesh_.cells.size(); ++e) {
    const auto nodes = mesh_.cells.nodes(e);
    if (std::none_of(nodes.begin(), nodes.end(), [&](int n) { return node_point[n] >= 0; }))
      continue;
    for (std::size_t a = 0; a < nodes.size(); ++a) x[a] = mesh_.x[nodes[a]];
    kin.compute(reference_table(mesh_.cells.type[e]), std::span<const Vec3>(x, nodes.size()));
    const ElasticConstants k = material_of(e).at(temperature_.reference);
    const double c = (k.lame_lambda() + 4 * k.shear_modulus()) / 3;
    for (int q = 0; q < kin.points; ++q)
      for (std::size_t a = 0; a < nodes.size(); ++a)
        if (const int i = node_point[nodes[a]]; i >= 0) {
          const double* g = kin.grad(q) + 3 * a;
          points[i].stiffness += c * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) * kin.dv[q];
        }
  }
}

std::string Model::start_contact(ContactBody& body, const std::vector<int>* node_owner) const {
  // A node that starts inside the rigid body by more than the allowed penetration is a set-up
  // error (the surface or the mesh is misplaced), not something to push out.
  const ContactSpec& spec = *body.spec;
  const Vec3 m0 = body.motion(0);
  std::string error;
  for (std::size_t i = 0; i < body.points.size(); ++i) {
    const ContactPoint& p = body.points[i];
    const double d = body.points[i].gap0 = body.surface->signed_distance(p.x - m0);
    if (!error.empty() || (node_owner && (*node_owner)[p.node] != par::rank()) ||
        d >= -body.allowed_gap(static_cast<int>(i)))
      continue;
    const Vec3& x = mesh_.x[p.node];
    error = fmt::format(
        "contact '{}': node {} of region '{}' at ({:g}, {:g}, {:g}) starts inside the rigid "
        "surface, {:.3g} below it (allowed: {:.3g}, 'penetration' {:g} of the local element "
        "size); move the surface or the mesh so that they do not overlap at t = 0",
        spec.name, mesh_.node_tag[p.node], spec.nodes, x.x(), x.y(), x.z(), -d,
        body.allowed_gap(static_cast<int>(i)), spec.penetration);
  }
  return error;
}

namespace {

/// The nodes of a contact's region on this part: those of its faces here, and those whose
/// faces are all on other ranks (each rank flags its faces' nodes; the flags are summed over
/// the copies).
std::vector<int> region_nodes_of_part(const Region& region, int n, const NodeExchange& exchange) {
  std::vector<double> flag(n, 0.0);
  for (int v : region.nodes) flag[v] = 1;
  exchange.sum(flag, 1);
  std::vector<int> nodes;
  for (int v = 0; v < n; ++v)
    if (flag[v] > 0) nodes.push_back(v);
  return nodes;
}

/// Sums each point's area, Σ face area, face count and stiffness over its copies on the ranks,
/// and gives a mid-edge point the corners that every copy with a face at it gives (their whole
/// numbers, in increasing order). `local`: whole node -> this part's, filled on first use.
void sum_over_copies(ContactFaceSums& sums, const std::vector<int>& nodes, int n,
                     const MeshPart& part, const NodeExchange& exchange,
                     std::unordered_map<long long, int>& local) {
  constexpr int w = 7;  // area, Σ face area, faces, stiffness, mid-edge count, corners
  std::vector<double> v(static_cast<std::size_t>(w) * n, 0.0);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const ContactPoint& p = sums.points[i];
    double* x = &v[static_cast<std::size_t>(w) * nodes[i]];
    x[0] = p.area;
    x[1] = sums.size2[i];
    x[2] = sums.faces[i];
    x[3] = p.stiffness;
    if (p.terms == 3) {
      const long long a = part.global_node[p.term_node[1]], b = part.global_node[p.term_node[2]];
      x[4] = 1;
      x[5] = static_cast<double>(std::min(a, b));
      x[6] = static_cast<double>(std::max(a, b));
    }
  }
  exchange.sum(v, w);
  if (local.empty())
    for (int k = 0; k < n; ++k) local.emplace(part.global_node[k], k);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    ContactPoint& p = sums.points[i];
    const double* x = &v[static_cast<std::size_t>(w) * nodes[i]];
    p.area = x[0];
    sums.size2[i] = x[1];
    sums.faces[i] = x[2];
    p.stiffness = x[3];
    if (x[4] > 0)  // every copy that has a face at it gives the same corners
      set_mid_edge_terms(p, local.at(std::llround(x[5] / x[4])),
                         local.at(std::llround(x[6] / x[4])));
  }
}

/// Sets the whole list's index of each point of `body` (ContactBody::whole_index) and the
/// whole list's length: the place of its node's whole number among the region's (a whole mesh
/// lists them in that order). Root sorts the owners' numbers (the region's, transiently) and
/// tells each its points' places; ghosts take their owners'. Collective.
void number_whole_points(ContactBody& body, int n, const MeshPart& part,
                         const NodeExchange& exchange) {
  std::vector<long long> own;
  for (const ContactPoint& p : body.points)
    if (p.node < part.owned_nodes) own.push_back(part.global_node[p.node]);
  const auto as_bytes = [](const std::vector<long long>& numbers) {
    return std::string(reinterpret_cast<const char*>(numbers.data()),
                       numbers.size() * sizeof(long long));
  };
  std::vector<std::string> places(par::size());
  if (const auto owners = par::gather_strings(as_bytes(own)); par::root()) {
    std::vector<std::tuple<long long, int, int>> all;  // whole number, rank, place there
    for (int r = 0; r < par::size(); ++r)
      for (std::size_t k = 0; k < owners[r].size() / sizeof(long long); ++k) {
        long long g = 0;
        std::memcpy(&g, owners[r].data() + k * sizeof g, sizeof g);
        all.emplace_back(g, r, static_cast<int>(k));
      }
    std::sort(all.begin(), all.end());
    std::vector<std::vector<long long>> at(par::size());
    for (int r = 0; r < par::size(); ++r) at[r].resize(owners[r].size() / sizeof(long long));
    for (std::size_t i = 0; i < all.size(); ++i)
      at[std::get<1>(all[i])][std::get<2>(all[i])] = static_cast<long long>(i);
    for (int r = 0; r < par::size(); ++r) places[r] = as_bytes(at[r]);
  }
  const std::string mine = par::exchange_bytes(places)[0];
  HENCKY_VERIFY(mine.size() == own.size() * sizeof(long long),
                "number_whole_points: root sent the wrong number of places");
  std::vector<double> index(n, -1.0);
  std::size_t k = 0;
  for (const ContactPoint& p : body.points)
    if (p.node < part.owned_nodes) {
      long long place = 0;
      std::memcpy(&place, mine.data() + k++ * sizeof place, sizeof place);
      index[p.node] = static_cast<double>(place);
    }
  exchange.to_ghosts(index, 1);
  body.whole_points = static_cast<int>(par::sum(static_cast<long long>(own.size())));
  body.whole_index.clear();
  for (const ContactPoint& p : body.points)
    body.whole_index.push_back(static_cast<int>(std::llround(index[p.node])));
}

}  // namespace

void Model::bind_contact_of_part() {
  // Each rank has the region's faces of its part, and its own cells. A node of the region is a
  // point on every rank that holds it, also where its faces are all on other ranks: the ranks
  // flag the region's nodes and sum their faces' areas, sizes and cells' stiffness over the
  // copies. A mid-edge point's corners are told by their whole numbers, in increasing order,
  // so that every copy computes its position alike. The points are in the whole mesh's order,
  // owners' first (the order of a whole mesh's region: its nodes are numbered owner by owner).
  const int n = mesh_.n_nodes();
  const MeshPart& part = *dist_.part;
  const NodeExchange& exchange = *dist_.exchange;
  std::unordered_map<long long, int> local;  // whole node -> this part's
  for (ContactBody& body : contacts_) {
    const ContactSpec& spec = *body.spec;
    const Region& region = find_region(spec.nodes, spec.nodes_where, 2, 2, "physical surface");
    const std::vector<int> nodes = region_nodes_of_part(region, n, exchange);
    ContactFaceSums sums;
    // The first zero-area face in the whole mesh's order is the lowest rank's first.
    std::string error;
    try {
      sums = contact_face_sums(mesh_, region, nodes, spec.nodes_where);
    } catch (const InputError& e) {
      error = e.message();
    }
    if (error = par::first_error(error); !error.empty()) throw InputError(spec.nodes_where, error);
    add_contact_stiffness(sums.points);  // this rank's cells' share
    sum_over_copies(sums, nodes, n, part, exchange, local);
    body.points = finish_contact_points(mesh_, std::move(sums));
    number_whole_points(body, n, part, exchange);
    // The first node inside the surface in the whole order is the lowest rank's first own.
    error = par::first_error(start_contact(body, &part.node_owner));
    if (!error.empty()) throw InputError(spec.surface.where, error);
  }
}

}  // namespace hencky
