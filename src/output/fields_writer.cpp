// The fields files of the written steps (fields_writer.hpp).
#include "output/fields_writer.hpp"

#include <fmt/format.h>

#include <deque>

#include "core/error.hpp"
#include "core/invariant.hpp"
#include "material/elastic.hpp"
#include "output/tensor_order.hpp"
#include "parallel/mesh_part.hpp"
#include "parallel/mpi.hpp"

namespace hencky {
namespace fs = std::filesystem;
using namespace tensor_order;

namespace {
/// The point law's internal variables by their names (Model::law_variables), at the piece's n
/// nodes (`node`: the model's node of each): a tensor in ParaView's order, like the stress.
/// `store` keeps the arrays the fields' spans point into.
template <class NodeOf>
void add_law_fields(const Model& model, const RecoveredFields& fields, int n, NodeOf node,
                    std::deque<std::vector<double>>& store, std::vector<VtuField>& out) {
  std::size_t offset = 0;
  const std::size_t n_law = model.law_state_size();
  for (const LawVariable& var : model.law_variables()) {
    auto& values = store.emplace_back(static_cast<std::size_t>(var.size) * n);
    for (int i = 0; i < n; ++i) {
      const double* v = &fields.nodal_internal[n_law * node(i) + offset];
      for (int c = 0; c < var.size; ++c)
        values[var.size * i + c] = v[var.size == 6 ? paraview_order[c] : c];
    }
    out.push_back({var.name, var.size, values});
    offset += var.size;
  }
}
}  // namespace

FieldsWriter::FieldsWriter(const Model& model, fs::path dir)
    : model_(model), dir_(std::move(dir)), pieces_(par::size() > 1) {
  if (!pieces_) return;
  // The piece: this rank's part of the mesh, its own cells and the nodes they touch (its own,
  // then the ghosts).
  HENCKY_VERIFY(model_.partition().parts == par::size(),
                "FieldsWriter: the model is not split over the ranks");
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
  add_law_fields(model_, fields, n, node, gathered, point_fields);
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

}  // namespace hencky
