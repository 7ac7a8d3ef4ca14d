#include "solve/contact_step.hpp"

#include <fmt/format.h>

#include <cmath>

#include "parallel/mpi.hpp"

namespace hencky {

ContactStep::ContactStep(const Model& m, int max_flips)
    : max_flips_(max_flips),
      m_(&m),
      distributed_(m.layout().kind() == NodalLayout::Kind::distributed) {
  const auto& bodies = m.contacts();
  if (distributed_) {
    const Partition& part = m.partition();
    for (const ContactBody& body : bodies) {
      auto& owned = owned_.emplace_back();
      for (const ContactPoint& p : body.points)
        owned.push_back(part.node_owner[p.node] == part.rank);
    }
  }
  for (const ContactBody& body : bodies) {
    double lo = INFINITY, hi = 0;
    for (const ContactPoint& p : body.points) {
      lo = std::min(lo, p.stiffness);
      hi = std::max(hi, p.stiffness);
    }
    k_min_.push_back(-m.layout().largest(-lo));
    k_max_.push_back(m.layout().largest(hi));
  }
  m0_.assign(bodies.size(), Vec3::Zero());
  m1_.assign(bodies.size(), Vec3::Zero());
  flips_.resize(bodies.size());
  prev_gap_.resize(bodies.size());
  r_t_.resize(bodies.size());
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    flips_[b].assign(bodies[b].points.size(), 0);
    prev_gap_[b].assign(bodies[b].points.size(), NAN);
    r_t_[b].resize(bodies[b].points.size());
  }
}

Vec3 ContactStep::position(int body, int i, const std::vector<double>& u) const {
  return contact_position(m_->contacts()[body].points[i], u);
}

void ContactStep::initial(State& s) const {
  const auto& bodies = m_->contacts();
  s.f_contact.assign(m_->dofs().n_dofs(), 0.0);
  s.contact.assign(bodies.size(), {});
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const ContactBody& body = bodies[b];
    const Vec3 m0 = body.motion(0);
    auto& states = s.contact[b];
    states.resize(body.points.size());
    for (std::size_t i = 0; i < body.points.size(); ++i) {
      ContactNode& n = states[i];
      n.kappa = body.initial_kappa(static_cast<int>(i));
      n.gap = body.points[i].gap0;
      const SurfacePoint q = body.surface->nearest(body.points[i].x - m0);
      n.point = q.x + m0;
      n.normal = q.n;
      n.contact = body.touches_at_start(static_cast<int>(i));
    }
  }
}

void ContactStep::begin(const State& c, State& trial) {
  const auto& bodies = m_->contacts();
  trial.contact = c.contact;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    m0_[b] = bodies[b].motion(c.time);
    m1_[b] = bodies[b].motion(trial.time);
    for (ContactNode& n : trial.contact[b]) n.point += m1_[b] - m0_[b];
    std::fill(flips_[b].begin(), flips_[b].end(), 0);
    std::fill(prev_gap_[b].begin(), prev_gap_[b].end(), NAN);
    for (std::size_t i = 0; i < r_t_[b].size(); ++i)
      r_t_[b][i] = position(static_cast<int>(b), static_cast<int>(i), c.u);
  }
  progress_ = ContactProgress{};
  for (std::size_t b = 0; b < trial.contact.size(); ++b)
    for (std::size_t i = 0; i < trial.contact[b].size(); ++i)
      progress_.in_contact += counts(b, i) && trial.contact[b][i].contact;
  progress_.in_contact = static_cast<int>(m_->layout().total(progress_.in_contact));
}

void ContactStep::forces(State& trial) const {
  const auto& bodies = m_->contacts();
  trial.f_contact.assign(m_->dofs().n_dofs(), 0.0);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    for (std::size_t i = 0; i < bodies[b].points.size(); ++i) {
      const ContactNode& s = trial.contact[b][i];
      if (!s.contact || !counts(b, i)) continue;
      const Vec3 f = contact_force(s, position(static_cast<int>(b), static_cast<int>(i), trial.u));
      // f = T̃ᵀ F̃: the transformed node's force spread on the mesh nodes it stands for.
      const ContactPoint& p = bodies[b].points[i];
      for (int k = 0; k < p.terms; ++k)
        for (int d = 0; d < 3; ++d) trial.f_contact[3 * p.term_node[k] + d] += p.term_coef[k] * f[d];
    }
  // Each point's forces came from one rank: summed over the copies of the nodes.
  if (distributed_) m_->layout().sum(trial.f_contact, 3);
}

void ContactStep::add_matrix(const State& trial,
                             const std::function<void(int, int, const Mat3&)>& add) {
  const auto& bodies = m_->contacts();
  for (std::size_t b = 0; b < bodies.size(); ++b)
    for (std::size_t i = 0; i < bodies[b].points.size(); ++i) {
      const ContactNode& s = trial.contact[b][i];
      if (!s.contact || !counts(b, i)) continue;
      const Mat3 G = contact_matrix(s);
      const ContactPoint& p = bodies[b].points[i];
      // T̃ᵀ G T̃ over the (up to three) mesh nodes of the point.
      for (int j = 0; j < p.terms; ++j)
        for (int k = 0; k < p.terms; ++k)
          add(p.term_node[j], p.term_node[k], (p.term_coef[j] * p.term_coef[k]) * G);
    }
  assembled_ = trial.contact;
  assembled_any_ = true;
}

void ContactStep::add_matrix(const State& trial, std::span<double> values) {
  const auto& eq = m_->dofs().eq;
  const auto& pattern = m_->assembler().pattern();
  // One triangle of the symmetric matrix: each global pair once, from the ordering in which its
  // row is the smaller.
  add_matrix(trial, [&](int a, int b, const Mat3& block) {
    for (int dj = 0; dj < 3; ++dj)
      for (int dk = 0; dk < 3; ++dk) {
        const int gj = eq[3 * a + dj], gk = eq[3 * b + dk];
        if (gj < 0 || gk < 0 || gj > gk) continue;
        values[pattern.find(gj, gk)] += block(dj, dk);
      }
  });
}

bool ContactStep::matrix_stale(const State& trial) const {
  if (!active()) return false;
  if (!assembled_any_) return true;
  bool stale = false;
  for (std::size_t b = 0; b < trial.contact.size() && !stale; ++b)
    for (std::size_t i = 0; i < trial.contact[b].size() && !stale; ++i) {
      const ContactNode &s = trial.contact[b][i], &a = assembled_[b][i];
      stale = s.contact != a.contact ||
              (s.contact && (s.kappa != a.kappa || (s.normal - a.normal).norm() > 1e-3));
    }
  return m_->layout().largest(stale) > 0;  // the ranks of a distributed mesh agree
}

ContactProgress ContactStep::update(const State& c, State& trial) {
  const auto& bodies = m_->contacts();
  ContactProgress pr;
  std::vector<std::pair<int, int>> raise;  // (surface, point) whose κ the strategy raises
  std::string oscillates;                  // the first node whose contact set oscillates
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const ContactBody& body = bodies[b];
    const SurfaceMotion where{body.surface.get(), m0_[b], m1_[b]};
    for (std::size_t i = 0; i < body.points.size(); ++i) {
      const int ii = static_cast<int>(i);
      ContactNode& s = trial.contact[b][i];
      const bool was_contact = s.contact, was_separation = s.separation;
      const ContactBranch branch = update_contact_node(
          s, c.contact[b][i], r_t_[b][i], position(static_cast<int>(b), ii, trial.u), where);
      const bool mine = counts(b, i);
      if (branch == ContactBranch::released && c.contact[b][i].contact && mine) ++pr.released;
      if (s.contact != was_contact || s.separation != was_separation) pr.set_changed = true;
      if (s.contact != was_contact && ++flips_[b][i] > max_flips_ && oscillates.empty())
        oscillates = fmt::format(
            "contact '{}': node {} changed between contact and no contact {} times in this "
            "step (the contact set oscillates)",
            body.spec->name, m_->mesh().node_tag[body.points[i].node], flips_[b][i]);
      pr.max_penetration = std::max(pr.max_penetration, -s.gap);
      if (!s.contact) {
        prev_gap_[b][i] = NAN;
        continue;
      }
      pr.in_contact += mine;
      const double allowed = body.allowed_gap(ii), g = std::abs(s.gap);
      pr.worst_gap = std::max(pr.worst_gap, allowed > 0 ? g / allowed : 0.0);
      // κ strategy (auto): the augmented update (3.4) removes the fraction κ/(κ + k) of the
      // gap per iteration, k the stiffness the node meets. Where the gap is still above the
      // allowed one and did not at least halve since the last update, κ is too small for the
      // node: raise it tenfold (up to 1e4 times its start).
      if (!body.spec->stiffness && g > allowed && std::isfinite(prev_gap_[b][i]) &&
          g > 0.5 * prev_gap_[b][i] && s.kappa < 1e4 * body.initial_kappa(ii))
        raise.push_back({static_cast<int>(b), ii});
      prev_gap_[b][i] = g;
    }
  }
  // On a distributed mesh every copy of a point took the same branch; the ranks agree on the
  // whole's figures, and on an oscillation that one of them found (its message is root's to
  // give: the first in rank order).
  const NodalLayout& layout = m_->layout();
  if (distributed_) {
    double sums[2] = {static_cast<double>(pr.released), static_cast<double>(pr.in_contact)};
    double most[4] = {static_cast<double>(pr.set_changed), pr.max_penetration, pr.worst_gap,
                      static_cast<double>(!oscillates.empty())};
    par::sum_in_place(sums);
    par::max_in_place(most);
    pr.released = static_cast<int>(sums[0]);
    pr.in_contact = static_cast<int>(sums[1]);
    pr.set_changed = most[0] > 0;
    pr.max_penetration = most[1];
    pr.worst_gap = most[2];
    if (most[3] > 0) {
      std::string first;
      for (const std::string& m : par::gather_strings(oscillates))
        if (first.empty()) first = m;
      throw SolveError(par::root() ? first : "the contact set oscillates on another rank");
    }
  } else if (!oscillates.empty()) {
    throw SolveError(oscillates);
  }
  // Only while the contact set holds still: while it changes, gaps jump for other reasons
  // than a small κ, and a stiffer κ then only sharpens the jumps.
  if (!pr.set_changed)
    for (const auto& [b, i] : raise) {
      trial.contact[b][i].kappa *= 10;
      pr.kappa_raised = true;
    }
  pr.kappa_raised = layout.largest(pr.kappa_raised) > 0;
  progress_ = pr;
  return pr;
}

int ContactStep::release_pulling(const State& c, State& trial, double limit) {
  const auto& bodies = m_->contacts();
  int released = 0;
  for (std::size_t b = 0; b < bodies.size(); ++b)
    for (std::size_t i = 0; i < bodies[b].points.size(); ++i) {
      ContactNode& s = trial.contact[b][i];
      if (!s.contact) continue;
      const Vec3 r = position(static_cast<int>(b), static_cast<int>(i), trial.u);
      if (contact_force(s, r).dot(s.normal) >= -limit) continue;
      release_contact_node(s, c.contact[b][i]);
      ++flips_[b][i];
      released += counts(b, i);
    }
  released = static_cast<int>(m_->layout().total(released));
  if (released > 0) {
    progress_.set_changed = true;
    progress_.in_contact -= released;
  }
  return released;
}

void ContactStep::augmented_offsets(const State& s, std::vector<double>& c,
                                    std::vector<double>* weight) const {
  c.clear();
  if (weight) weight->clear();
  for (const auto& nodes : s.contact)
    for (const ContactNode& n : nodes) {
      c.push_back(contact_force(n, Vec3::Zero()).dot(n.normal));  // 0 out of contact
      if (weight) weight->push_back(n.contact ? 1 / n.kappa : 0.0);
    }
  if (weight && distributed_) {  // a point's rows count at its node's owner alone
    std::size_t k = 0;
    for (std::size_t b = 0; b < s.contact.size(); ++b)
      for (std::size_t i = 0; i < s.contact[b].size(); ++i, ++k)
        if (!counts(b, i)) (*weight)[k] = 0;
  }
}

void ContactStep::set_augmented_offsets(State& s, std::span<const double> c) const {
  std::size_t i = 0;
  for (auto& nodes : s.contact)
    for (ContactNode& n : nodes) {
      if (n.contact) n.force = (c[i] - n.kappa * n.point.dot(n.normal)) * n.normal;
      ++i;
    }
}

std::string ContactStep::diagnosis() const {
  if (!active()) return {};
  std::string s;
  if (progress_.set_changed)
    s = "the contact set still changed in the last iteration";
  else if (progress_.worst_gap > 1)
    s = fmt::format("the largest gap of a node in contact is {:.3g} times the allowed one",
                    progress_.worst_gap);
  // A given κ far below the mesh's stiffness makes the augmented update (3.4) close the gaps
  // and settle the forces slowly: the residual then falls by about k/(k + κ) per iteration.
  for (std::size_t k = 0; k < m_->contacts().size(); ++k) {
    const ContactBody& b = m_->contacts()[k];
    if (!b.spec->stiffness) continue;
    const double k_min = k_min_[k], k_max = k_max_[k];
    const double kappa = *b.spec->stiffness;
    const char* sep = s.empty() ? "" : "; ";
    if (kappa < auto_kappa_factor * k_min / 10)
      s += fmt::format("{}contact '{}': stiffness {:.3g} is small against the mesh's stiffness "
                       "(auto would start at {:.3g} or more), so the contact forces settle "
                       "slowly; try stiffness: auto",
                       sep, b.spec->name, kappa, auto_kappa_factor * k_min);
    else if (kappa > 1e3 * auto_kappa_factor * k_max)
      s += fmt::format("{}contact '{}': stiffness {:.3g} is more than 1e4 times the mesh's "
                       "stiffness ({:.3g} at most), and round-off in the solve hides the "
                       "small forces of the body; try stiffness: auto",
                       sep, b.spec->name, kappa, k_max);
  }
  return s;
}

std::string ContactStep::summary(const State& s) const {
  std::string out;
  const auto& bodies = m_->contacts();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    ContactTotals t;
    if (!distributed_) {
      t = contact_totals(bodies[b], s.contact[b], s.u);
    } else {  // each point at its node's owner, over the ranks
      const Partition& part = m_->partition();
      t = contact_totals(bodies[b], s.contact[b], s.u, &part.node_owner, part.rank);
      double sums[2] = {t.force, static_cast<double>(t.nodes)};
      double most[2] = {t.max_penetration, t.max_penetration_relative};
      par::sum_in_place(sums);
      par::max_in_place(most);
      t.force = sums[0];
      t.nodes = static_cast<int>(sums[1]);
      t.max_penetration = most[0];
      t.max_penetration_relative = most[1];
    }
    if (!out.empty()) out += "; ";
    out += fmt::format("contact '{}': {} nodes, normal force {:.4g}, largest penetration {:.2e} "
                       "({:.1e} of the element size)",
                       bodies[b].spec->name, t.nodes, t.force, t.max_penetration,
                       t.max_penetration_relative);
  }
  return out;
}

}  // namespace hencky
