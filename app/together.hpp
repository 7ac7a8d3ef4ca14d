#pragma once
// Steps of the command line that no rank may fail alone (app/).
#include <fmt/format.h>

#include <exception>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "parallel/mpi.hpp"

namespace hencky::cli {

/// Steps no rank may fail alone: every rank reports whether `f` threw, and all stop together
/// when one did. Root prints each rank's message once (ranks with the same message together).
/// Returns the exit status (0: all went well).
template <class F>
int together(F&& f) {
  int code = 0;
  std::string message;
  try {
    f();
  } catch (const InputError& e) {
    code = 1, message = std::string("error: ") + e.what();
  } catch (const std::exception& e) {
    code = 3, message = std::string("internal error: ") + e.what();
  }
  if (par::size() == 1) {
    if (code) std::cerr << message << "\n";
    return code;
  }
  const int worst = par::max(code);
  if (worst == 0) return 0;
  const auto messages = par::gather_strings(code ? message : std::string());
  if (par::root()) {
    std::map<std::string, std::vector<int>> ranks_of;
    for (std::size_t r = 0; r < messages.size(); ++r)
      if (!messages[r].empty()) ranks_of[messages[r]].push_back(static_cast<int>(r));
    for (const auto& [text, ranks] : ranks_of) {
      if (ranks.size() == messages.size()) {
        std::cerr << text << "\n";
        continue;
      }
      std::string who;
      for (int r : ranks) who += (who.empty() ? "" : ", ") + std::to_string(r);
      std::cerr << fmt::format("rank{} {}: {}\n", ranks.size() > 1 ? "s" : "", who, text);
    }
  }
  return worst;
}

}  // namespace hencky::cli
