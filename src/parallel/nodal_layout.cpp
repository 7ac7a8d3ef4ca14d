#include "parallel/nodal_layout.hpp"

#include <stdexcept>

#include "parallel/mpi.hpp"
#include "parallel/node_exchange.hpp"

namespace hencky {

NodalLayout NodalLayout::replicated() {
  NodalLayout l;
  l.kind_ = Kind::replicated;
  return l;
}

NodalLayout NodalLayout::distributed(std::shared_ptr<const NodeExchange> exchange) {
  if (!exchange) throw std::invalid_argument("NodalLayout::distributed: no exchange");
  NodalLayout l;
  l.kind_ = Kind::distributed;
  l.exchange_ = std::move(exchange);
  return l;
}

void NodalLayout::sum(std::span<double> v, int width) const {
  switch (kind_) {
    case Kind::whole:
      return;
    case Kind::replicated:
      par::sum_in_place(v);
      return;
    case Kind::distributed:
      exchange_->sum(v, width);
      return;
  }
}

void NodalLayout::sum_blocks(std::span<double> v, int blocks) const {
  if (kind_ != Kind::distributed) return sum(v, 1);
  const std::size_t n = v.size() / blocks;
  for (int b = 0; b < blocks; ++b) exchange_->sum(v.subspan(b * n, n), 1);
}

std::size_t NodalLayout::owned_entries(std::size_t size, int width, int local_nodes) const {
  if (kind_ != Kind::distributed) return size;
  if (local_nodes != exchange_->local_nodes() ||
      size != static_cast<std::size_t>(width) * local_nodes)
    throw std::invalid_argument("NodalLayout: a vector that is not of this rank's nodes");
  return static_cast<std::size_t>(width) * exchange_->owned_nodes();
}

int NodalLayout::owned_free(std::span<const int> eq, int per_node) const {
  const std::size_t own =
      kind_ == Kind::distributed ? owned_entries(eq.size(), per_node, exchange_->local_nodes())
                                 : eq.size();
  int n = 0;
  for (std::size_t i = 0; i < own; ++i) n += eq[i] >= 0;
  return n;
}

double NodalLayout::dot(std::span<const double> a, std::span<const double> b,
                        std::size_t owned) const {
  double s = 0;
  for (std::size_t i = 0; i < owned; ++i) s += a[i] * b[i];
  return total(s);
}

double NodalLayout::total(double x) const {
  if (kind_ != Kind::distributed) return x;
  par::sum_in_place(std::span<double>(&x, 1));
  return x;
}

void NodalLayout::total(std::span<double> x) const {
  if (kind_ == Kind::distributed) par::sum_in_place(x);
}

double NodalLayout::largest(double x) const {
  if (kind_ != Kind::distributed) return x;
  par::max_in_place(std::span<double>(&x, 1));
  return x;
}

}  // namespace hencky
