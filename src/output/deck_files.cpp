#include "output/deck_files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "fem/reference_element.hpp"
#include "output/frd_writer.hpp"
#include "output/tensor_order.hpp"
#include "parallel/mpi.hpp"
#include "solve/recovery.hpp"

namespace hencky {

namespace fs = std::filesystem;

namespace {

/// Fortran's 1p e13.6 (ccx's value fields): d.ddddddE+ee, right-aligned in 13.
std::string e13(double v) {
  return fmt::format("{:13.6E}", v == 0 ? 0.0 : v);  // no "-0.000000E+00"
}

/// Fortran's e14.7 (the time of ccx's block titles): 0.dddddddE+ee, right-aligned in 14.
std::string e14(double v) {
  if (v == 0) return " 0.0000000E+00";
  int e = static_cast<int>(std::floor(std::log10(std::abs(v)))) + 1;
  double m = v / std::pow(10.0, e);
  if (std::abs(std::round(std::abs(m) * 1e7)) >= 1e7) {  // rounds up to 1.0000000
    m /= 10;
    ++e;
  }
  return fmt::format("{:>14}", fmt::format("{}0.{:07.0f}E{}{:02d}", m < 0 ? "-" : "",
                                           std::abs(m) * 1e7, e < 0 ? '-' : '+', std::abs(e)));
}

/// ccx's natural coordinates of its full rule's points for a cell type (gauss.f), in its order.
std::vector<std::array<double, 3>> ccx_points(CellType type) {
  std::vector<std::array<double, 3>> p;
  auto hex = [&](std::vector<double> g) {
    for (double z : g)
      for (double y : g)
        for (double x : g) p.push_back({x, y, z});
  };
  const double a = 0.138196601125011, b = 0.585410196624968;
  switch (type) {
    case CellType::tet4:
      p.push_back({0.25, 0.25, 0.25});
      break;
    case CellType::tet10:
      p = {{a, a, a}, {b, a, a}, {a, b, a}, {a, a, b}};
      break;
    case CellType::hex8:
      hex({-1 / std::sqrt(3.0), 1 / std::sqrt(3.0)});
      break;
    case CellType::hex20:
      hex({-std::sqrt(0.6), 0.0, std::sqrt(0.6)});
      break;
    case CellType::wedge6:
      p = {{1 / 3.0, 1 / 3.0, -1 / std::sqrt(3.0)}, {1 / 3.0, 1 / 3.0, 1 / std::sqrt(3.0)}};
      break;
    default:
      break;
  }
  return p;
}

/// The nodal field `variable` of a *NODE FILE or *EL FILE request as ccx names its .frd block,
/// added to `out` once.
void frd_field(const std::string& variable, const State& state, const RecoveredFields& fields,
               std::vector<FrdField>& out) {
  const std::size_t n = state.u.size() / 3;
  FrdField f;
  auto take = [&](const std::vector<double>& v, std::size_t k) {
    f.values.assign(n * k, 0.0);
    if (v.size() == n * k) f.values = v;
  };
  if (variable == "U") {
    f = {"DISP", {"D1", "D2", "D3"}, {}};
    take(state.u, 3);
  } else if (variable == "RF") {
    f = {"FORC", {"F1", "F2", "F3"}, {}};
    take(state.f_int, 3);
  } else if (variable == "NT") {
    f = {"NDTEMP", {"T"}, {}};
    take(state.nodal_temperature, 1);
  } else if (variable == "PEEQ") {
    f = {"PE", {"PE"}, {}};
    take(fields.nodal_eps_p_eq, 1);
  } else if (variable == "E" || variable == "S") {
    // ccx's TOSTRAIN and STRESS: XX YY ZZ XY YZ ZX, ParaView's order; strains with tensor shears.
    const bool strain = variable == "E";
    f = strain ? FrdField{"TOSTRAIN", {"EXX", "EYY", "EZZ", "EXY", "EYZ", "EZX"}, {}}
               : FrdField{"STRESS", {"SXX", "SYY", "SZZ", "SXY", "SYZ", "SZX"}, {}};
    const std::vector<Voigt>& v = strain ? fields.nodal_strain : fields.nodal_stress;
    f.values.assign(n * 6, 0.0);
    if (v.size() == n)
      for (std::size_t a = 0; a < n; ++a)
        for (int c = 0; c < 6; ++c)
          f.values[6 * a + static_cast<std::size_t>(c)] =
              strain ? tensor_order::tensor_component(v[a], c)
                     : v[a][tensor_order::paraview_order[static_cast<std::size_t>(c)]];
  } else {
    return;
  }
  for (const FrdField& g : out)
    if (g.name == f.name) return;
  out.push_back(std::move(f));
}

}  // namespace

std::vector<int> ccx_point_order(CellType type) {
  const ReferenceTable& tab = reference_table(type);
  const auto ccx = ccx_points(type);
  if (ccx.size() != static_cast<std::size_t>(tab.n_points)) return {};
  std::vector<int> order;
  for (const auto& c : ccx) {
    int found = -1;
    for (int q = 0; q < tab.n_points; ++q)
      if (std::abs(tab.points[q][0] - c[0]) + std::abs(tab.points[q][1] - c[1]) +
              std::abs(tab.points[q][2] - c[2]) <
          1e-9)
        found = q;
    if (found < 0) return {};
    order.push_back(found);
  }
  return order;
}

DeckFiles::DeckFiles(const Model& model, const fs::path& dir) : model_(model) {
  const OutputSpec& out = model.spec().output;
  // Each print request's nodes (elements) in ascending labels, and each cell type's points in
  // ccx's order: once, not at every step written.
  for (const DeckRequest& q : out.deck_requests)
    members_.push_back(q.kind == DeckRequest::Kind::el_print     ? cells_of(q)
                       : q.kind == DeckRequest::Kind::node_print ? nodes_of(q)
                                                                 : std::vector<int>{});
  for (const CellType t :
       {CellType::tet4, CellType::tet10, CellType::hex8, CellType::hex20, CellType::wedge6}) {
    const auto k = static_cast<std::size_t>(t);
    if (point_order_.size() <= k) point_order_.resize(k + 1);
    point_order_[k] = ccx_point_order(t);
  }
  if (!out.deck_dat.empty()) {
    dat_.open(dir / out.deck_dat);
    if (!dat_) throw OutputError("cannot write " + (dir / out.deck_dat).string());
  }
  if (!out.deck_frd.empty()) {
    // The deck's materials, numbered in its order as ccx numbers them (those of its sections).
    FrdWriter::Materials m;
    for (const MaterialSpec& spec : model.spec().materials) m.names.push_back(spec.name);
    for (int c = 0; c < model.mesh().cells.size(); ++c)
      m.of_cell.push_back(model.material_index(c) + 1);
    frd_ = std::make_unique<FrdWriter>(dir / out.deck_frd, model.mesh(), m);
  }
}

DeckFiles::~DeckFiles() = default;

void DeckFiles::count_increment(double t) {
  // The requests of one deck step share its span.
  for (const DeckRequest& q : model_.spec().output.deck_requests)
    if (t > q.start && t <= q.end + 1e-9 * std::max(1.0, std::abs(q.end))) {
      if (q.start != step_start_) {
        step_start_ = q.start;
        increment_ = 0;
      }
      ++increment_;
      return;
    }
}

void DeckFiles::continue_from(const fs::path& old, double t, const std::vector<double>& earlier) {
  for (double e : earlier) count_increment(e);
  const double slack = 1e-6 * std::max(1.0, std::abs(t));  // the .dat's 7 digits
  const std::string& dat = model_.spec().output.deck_dat;
  if (dat_.is_open()) {
    // Every block up to the first one after t ("... for set NALL and time  0.1000000E+02").
    // A block starts with an empty line, which goes with it.
    std::ifstream in(old / dat);
    std::string line;
    int empty = 0;  // empty lines read and not written yet
    while (std::getline(in, line)) {
      if (line.empty()) {
        ++empty;
        continue;
      }
      const auto at = line.find(" and time ");
      if (at != std::string::npos && std::strtod(line.c_str() + at + 10, nullptr) > t + slack)
        break;
      for (; empty > 0; --empty) dat_ << '\n';
      dat_ << line << '\n';
    }
    dat_.flush();
  }
  if (frd_) frd_steps_ = frd_->adopt(old / model_.spec().output.deck_frd, t);
}

bool DeckFiles::due(const DeckRequest& q, double t, int increment) const {
  const double slack = 1e-9 * std::max(1.0, std::abs(q.end));
  if (!(t > q.start + slack && t <= q.end + slack) || q.frequency <= 0) return false;
  return increment % q.frequency == 0 || std::abs(t - q.end) <= slack;
}

std::vector<int> DeckFiles::nodes_of(const DeckRequest& q) const {
  const Mesh& mesh = model_.mesh();
  std::vector<int> nodes;
  if (q.set.empty()) {
    nodes.resize(static_cast<std::size_t>(mesh.n_nodes()));
    for (int n = 0; n < mesh.n_nodes(); ++n) nodes[static_cast<std::size_t>(n)] = n;
  } else if (const Region* r = mesh.find_region(q.set, 0, 0, true)) {
    nodes = r->nodes;
  } else if (const Region* any = mesh.find_region(q.set, 0, 3, true)) {
    nodes = any->nodes;
  }
  std::sort(nodes.begin(), nodes.end(),
            [&](int a, int b) { return mesh.node_tag[a] < mesh.node_tag[b]; });
  return nodes;
}

std::vector<int> DeckFiles::cells_of(const DeckRequest& q) const {
  const Mesh& mesh = model_.mesh();
  std::vector<int> cells;
  if (q.set.empty()) {
    for (int c = 0; c < mesh.cells.size(); ++c) cells.push_back(c);
  } else if (const Region* r = mesh.find_region(q.set, 3, 3, true)) {
    cells = r->cells;
  }
  std::sort(cells.begin(), cells.end(),
            [&](int a, int b) { return mesh.cells.tag[a] < mesh.cells.tag[b]; });
  return cells;
}

void DeckFiles::node_block(std::size_t index, const std::string& variable, const State& state,
                           double t) {
  const DeckRequest& q = model_.spec().output.deck_requests[index];
  const Mesh& mesh = model_.mesh();
  const std::string set = q.set.empty() ? std::string("NALL") : q.set;
  const std::vector<int>& nodes = members_[index];
  if (variable == "NT") {
    dat_ << fmt::format("\n temperatures for set {} and time {}\n\n", set, e14(t));
    for (int n : nodes)
      dat_ << fmt::format("{:10d} {}\n", mesh.node_tag[n],
                          e13(state.nodal_temperature.empty() ? 0.0 : state.nodal_temperature[n]));
    return;
  }
  const bool rf = variable == "RF";
  const std::vector<double>& v = rf ? state.f_int : state.u;
  if (!rf || q.totals != DeckRequest::Totals::only) {
    dat_ << fmt::format("\n {} for set {} and time {}\n\n",
                        rf ? "forces (fx,fy,fz)" : "displacements (vx,vy,vz)", set, e14(t));
    for (int n : nodes)
      dat_ << fmt::format("{:10d} {} {} {}\n", mesh.node_tag[n], e13(v[3 * n]), e13(v[3 * n + 1]),
                          e13(v[3 * n + 2]));
  }
  if (rf && q.totals != DeckRequest::Totals::no) {
    double sum[3] = {0, 0, 0};
    for (int n : nodes)
      for (int d = 0; d < 3; ++d) sum[d] += v[3 * n + d];
    dat_ << fmt::format("\n total force (fx,fy,fz) for set {} and time {}\n\n", set, e14(t));
    dat_ << fmt::format("       {} {} {}\n", e13(sum[0]), e13(sum[1]), e13(sum[2]));
  }
}

void DeckFiles::element_block(std::size_t index, const std::string& variable, const State& state,
                              double t) {
  const DeckRequest& q = model_.spec().output.deck_requests[index];
  const Mesh& mesh = model_.mesh();
  const std::string set = q.set.empty() ? std::string("EALL") : q.set;
  const bool stress = variable == "S", strain = variable == "E";
  dat_ << (stress   ? fmt::format("\n stresses (elem, integ.pnt.,sxx,syy,szz,sxy,sxz,syz) for set "
                                    "{} and time {}\n\n",
                                  set, e14(t))
           : strain ? fmt::format("\n strains (elem, integ.pnt.,exx,eyy,ezz,exy,exz,eyz) for set "
                                  "{} and time {}\n\n",
                                  set, e14(t))
                    : fmt::format("\n equivalent plastic strain (elem, integ.pnt.,pe)for set {} "
                                  "and time {}\n\n",
                                  set, e14(t)));
  std::vector<Voigt> eps;
  for (int c : members_[index]) {
    if (!model_.holds_points(c)) continue;
    const std::vector<int>& order = point_order_[static_cast<std::size_t>(mesh.cells.type[c])];
    const int n = model_.point_offset(c + 1) - model_.point_offset(c);
    if (strain) point_strains(model_, state, c, eps);
    for (int j = 0; j < n; ++j) {
      const int q = order.empty() ? j : order[static_cast<std::size_t>(j)];
      const int p = model_.point_offset(c) + q;
      if (stress || strain) {
        // hencky's 11 22 33 23 31 12, ccx's xx yy zz xy xz yz; ccx's strains have the tensor
        // shears, hencky's the engineering ones (twice those).
        const Voigt s = stress ? state.stress[p] : eps[static_cast<std::size_t>(q)];
        const double h = stress ? 1.0 : 0.5;
        dat_ << fmt::format("{:10d}{:4d} {} {} {} {} {} {}\n", mesh.cells.tag[c], j + 1, e13(s[0]),
                            e13(s[1]), e13(s[2]), e13(h * s[5]), e13(h * s[4]), e13(h * s[3]));
      } else {
        dat_ << fmt::format("{:10d}{:4d} {}\n", mesh.cells.tag[c], j + 1,
                            e13(state.eps_p_eq.empty() ? 0.0 : state.eps_p_eq[p]));
      }
    }
  }
}

void DeckFiles::step_done(const StepReport& report, const State& state,
                          const RecoveredFields& fields) {
  const double t = report.time;
  const auto& requests = model_.spec().output.deck_requests;
  count_increment(t);
  std::vector<FrdField> frd;
  for (std::size_t i = 0; i < requests.size(); ++i) {
    const DeckRequest& q = requests[i];
    if (!due(q, t, increment_)) continue;
    for (const std::string& v : q.variables) switch (q.kind) {
        case DeckRequest::Kind::node_print:
          node_block(i, v, state, t);
          break;
        case DeckRequest::Kind::el_print:
          // On several ranks the points are spread over them: element blocks are serial only.
          if (par::size() == 1) element_block(i, v, state, t);
          break;
        case DeckRequest::Kind::node_file:
        case DeckRequest::Kind::el_file:
          frd_field(v, state, fields, frd);
          break;
      }
  }
  if (dat_.is_open()) {
    dat_.flush();
    if (!dat_) throw OutputError("cannot write " + model_.spec().output.deck_dat);
  }
  if (frd_ && !frd.empty()) frd_->step(++frd_steps_, t, frd);
}

}  // namespace hencky
