#include "parallel/shared_nodes.hpp"

#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "core/invariant.hpp"
#include "parallel/mpi.hpp"

namespace hencky {
namespace {

template <class T>
void append(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

template <class T>
std::vector<T> values(const std::string& bytes) {
  std::vector<T> v(bytes.size() / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
  return v;
}

}  // namespace

SharedNodes share_nodes(std::span<const long long> tags) {
  const int ranks = par::size(), me = par::rank();
  const std::size_t n = tags.size();
  bool bad = false;
  {
    std::unordered_set<long long> seen(n);
    for (long long t : tags) bad = bad || t <= 0 || !seen.insert(t).second;
  }
  if (par::any(bad))
    throw std::invalid_argument("share_nodes: a node tag that is not positive, or twice on a rank");
  auto meeting = [&](long long t) { return static_cast<int>(t % ranks); };

  // 1. Every holder names itself at the tag's meeting rank, which takes the lowest as owner
  //    and answers each holder, in the order of its question.
  std::vector<std::string> ask(ranks);
  for (long long t : tags) append(ask[meeting(t)], t);
  const std::vector<std::string> asked = par::exchange_bytes(ask);
  std::unordered_map<long long, int> lowest;
  for (int r = 0; r < ranks; ++r)  // in rank order: the first to ask is the lowest
    for (long long t : values<long long>(asked[r])) lowest.emplace(t, r);
  std::vector<std::string> answer(ranks);
  for (int r = 0; r < ranks; ++r)
    for (long long t : values<long long>(asked[r])) append(answer[r], lowest.at(t));
  const std::vector<std::string> answered = par::exchange_bytes(answer);

  SharedNodes out;
  out.owner.resize(n);
  {
    std::vector<std::size_t> at(ranks, 0);
    std::vector<std::vector<int>> owners(ranks);
    for (int r = 0; r < ranks; ++r) owners[r] = values<int>(answered[r]);
    for (std::size_t i = 0; i < n; ++i) {
      const int m = meeting(tags[i]);
      out.owner[i] = owners[m].at(at[m]++);
    }
  }

  // 2. The owners number their nodes in their order; a second meeting takes each owner's
  //    index to the tag's other holders.
  out.owner_index.assign(n, -1);
  std::vector<std::string> tell(ranks);
  for (std::size_t i = 0; i < n; ++i)
    if (out.owner[i] == me) {
      out.owner_index[i] = out.owned++;
      append(tell[meeting(tags[i])], tags[i]);
      append(tell[meeting(tags[i])], static_cast<long long>(out.owner_index[i]));
    }
  const std::vector<std::string> told = par::exchange_bytes(tell);
  std::unordered_map<long long, long long> index;
  for (int r = 0; r < ranks; ++r) {
    const auto v = values<long long>(told[r]);
    for (std::size_t k = 0; k + 1 < v.size(); k += 2) index.emplace(v[k], v[k + 1]);
  }
  std::vector<std::string> reply(ranks);
  for (int r = 0; r < ranks; ++r)
    for (long long t : values<long long>(asked[r])) append(reply[r], index.at(t));
  const std::vector<std::string> replied = par::exchange_bytes(reply);
  {
    std::vector<std::size_t> at(ranks, 0);
    std::vector<std::vector<long long>> got(ranks);
    for (int r = 0; r < ranks; ++r) got[r] = values<long long>(replied[r]);
    for (std::size_t i = 0; i < n; ++i) {
      const int m = meeting(tags[i]);
      const long long k = got[m].at(at[m]++);
      HENCKY_VERIFY(out.owner[i] != me || k == out.owner_index[i],
                    "share_nodes: an owner's index came back changed");
      out.owner_index[i] = static_cast<int>(k);
    }
  }

  // 3. The whole numbering: the owners' counts before each rank, then the index.
  const std::vector<long long> first = par::rank_offsets(out.owned);
  out.total = first[ranks];
  out.global.resize(n);
  for (std::size_t i = 0; i < n; ++i) out.global[i] = first[out.owner[i]] + out.owner_index[i];
  return out;
}

}  // namespace hencky
