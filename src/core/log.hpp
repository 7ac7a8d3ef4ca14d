#pragma once
// The run's messages: the terminal (unless quiet) and the log file in the output directory.
#include <fmt/format.h>

#include <cstdio>
#include <set>
#include <string>
#include <vector>

namespace hencky {

class Log {
 public:
  bool quiet = false;
  /// Nothing goes to the terminal, warnings included (the ranks other than 0 of a parallel run).
  bool silent = false;

  /// Progress and results for the terminal and the log.
  template <class... A>
  void info(fmt::format_string<A...> f, A&&... a) {
    emit(fmt::format(f, std::forward<A>(a)...), false);
  }
  /// Details that only go to the log file (per-iteration figures, timings).
  template <class... A>
  void detail(fmt::format_string<A...> f, A&&... a) {
    lines_.push_back(fmt::format(f, std::forward<A>(a)...));
    flush();
  }
  /// A warning, printed once however often it is raised.
  void warn(const std::string& text) { warn_once(text, text); }
  /// A warning printed only the first time `key` is raised (the text may vary, e.g. with values).
  void warn_once(const std::string& key, const std::string& text) {
    if (!warned_.insert(key).second) return;
    warnings_.push_back(text);
    emit("warning: " + text, true);
  }
  const std::vector<std::string>& warnings() const { return warnings_; }
  /// Every line so far, details included (what the log file holds).
  const std::vector<std::string>& lines() const { return lines_; }

  /// From now on every line also goes to this file (earlier lines are written first).
  void attach_file(const std::string& path) {
    file_ = std::fopen(path.c_str(), "w");
    written_ = 0;
    flush();
  }
  ~Log() {
    if (file_) std::fclose(file_);
  }

 private:
  void emit(const std::string& text, bool is_warning) {
    if (!silent && (!quiet || is_warning)) std::fprintf(stderr, "%s\n", text.c_str());
    lines_.push_back(text);
    flush();
  }
  void flush() {
    if (!file_) return;
    for (; written_ < lines_.size(); ++written_)
      std::fprintf(file_, "%s\n", lines_[written_].c_str());
    std::fflush(file_);
  }
  std::vector<std::string> lines_;
  std::vector<std::string> warnings_;
  std::set<std::string> warned_;
  std::FILE* file_ = nullptr;
  std::size_t written_ = 0;
};

}  // namespace hencky
