// A deck's output requests (*NODE PRINT, *EL PRINT, *NODE FILE, *EL FILE and Abaqus's
// *NODE OUTPUT, *ELEMENT OUTPUT): what MODEL.dat and MODEL.frd hold (input/inp_history.hpp;
// written by output/deck_files.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "input/inp_history.hpp"

namespace hencky::inp {

namespace {

/// The variables hencky writes for a kind of request.
const std::vector<std::string>& written(DeckRequest::Kind kind) {
  static const std::vector<std::string> node = {"U", "RF", "NT"}, element = {"S", "E", "PEEQ"};
  switch (kind) {
    case DeckRequest::Kind::node_print:
    case DeckRequest::Kind::node_file:
      return node;
    case DeckRequest::Kind::el_print:
    case DeckRequest::Kind::el_file:
      break;
  }
  return element;
}

}  // namespace

void DeckCase::output_request(InpReader& r, const Keyword& k, int at, int first, int end) {
  if (!in_step_) return refuse(r, at, "*" + k.name + " outside a *STEP");
  DeckRequest q;
  q.where = r.where(at);
  int frequencyf = -1;  // FREQUENCYF= of this card, -1: not given
  const bool nodes = k.name.rfind("NODE", 0) == 0;
  const bool file =
      k.name.find("FILE") != std::string::npos || k.name.find("OUTPUT") != std::string::npos;
  q.kind = nodes ? (file ? DeckRequest::Kind::node_file : DeckRequest::Kind::node_print)
                 : (file ? DeckRequest::Kind::el_file : DeckRequest::Kind::el_print);
  for (const auto& [p, v] : k.params) {
    if (p == "NSET" || p == "ELSET") {
      q.set = upper(unquote(v));  // as ccx writes it in the .dat's titles
      if (p == "NSET")
        r.node_targets(q.set, at);  // it must be an NSET
      else
        r.element_targets(q.set, at);
    } else if (p == "FREQUENCY" || p == "FREQUENCYF") {
      const double f = r.real(v, at, "frequency");  // 0: none
      if (!(f >= 0) || f != std::floor(f) || f > 1e9)
        throw r.fail(at, fmt::format("{}= is a whole number >= 0, found '{}'", p, v));
      // FREQUENCY= is its own family's (prints or files), FREQUENCYF= the files'.
      (p == "FREQUENCYF" ? frequencyf : q.frequency) = static_cast<int>(f);
    } else if (p == "TOTALS") {
      const std::string t = upper(v);
      q.totals = t == "YES"    ? DeckRequest::Totals::yes
                 : t == "ONLY" ? DeckRequest::Totals::only
                               : DeckRequest::Totals::no;
    } else if (p == "GLOBAL" || p == "OUTPUT" || p == "VARIABLE") {
      continue;  // the results are in the global system; no local one is read
    } else {
      note(r, at, fmt::format("*{}, {}=: left out", k.name, p));
    }
  }
  for (int l = first; l < end; ++l)
    for (auto f : r.data(l)) {
      const std::string v = upper(f);
      const auto& w = written(q.kind);
      if (std::find(w.begin(), w.end(), v) != w.end())
        q.variables.push_back(v);
      else
        note(r, l,
             fmt::format("*{}: {} is not written (hencky writes {})", k.name, v,
                         fmt::join(w, ", ")));
    }
  requests_.resize(steps_.size());
  frequency_.resize(steps_.size(),
                    frequency_.empty() ? std::array<int, 2>{1, 1} : frequency_.back());
  // ccx (elprints.f, nodeprints.f, noelfiles.f): FREQUENCY=0 drops the request; a frequency
  // above 0 is that of every request of its family (prints, files) from then on.
  if (frequencyf > 0) frequency_.back()[1] = frequencyf;
  if (k.has("FREQUENCY")) {
    if (q.frequency == 0) return;
    frequency_.back()[q.prints() ? 0 : 1] = q.frequency;
  }
  requests_.back().push_back(std::move(q));
}

void DeckCase::build_requests() {
  // A step without requests of a kind keeps the last step's, as ccx does.
  requests_.resize(steps_.size());
  frequency_.resize(steps_.size(),
                    frequency_.empty() ? std::array<int, 2>{1, 1} : frequency_.back());
  std::vector<DeckRequest> active;
  bool dat = false, frd = false;
  for (std::size_t s = 0; s < steps_.size(); ++s) {
    for (auto kind : {DeckRequest::Kind::node_print, DeckRequest::Kind::el_print,
                      DeckRequest::Kind::node_file, DeckRequest::Kind::el_file}) {
      const auto mine = [&](const DeckRequest& q) { return q.kind == kind; };
      if (std::none_of(requests_[s].begin(), requests_[s].end(), mine)) continue;
      active.erase(std::remove_if(active.begin(), active.end(), mine), active.end());
      std::copy_if(requests_[s].begin(), requests_[s].end(), std::back_inserter(active), mine);
    }
    for (DeckRequest q : active) {
      q.start = steps_[s].start;
      q.end = steps_[s].end;
      q.frequency = frequency_[s][q.prints() ? 0 : 1];
      (q.prints() ? dat : frd) = true;
      spec_.output.deck_requests.push_back(std::move(q));
    }
  }
  const std::string stem = spec_.file.stem().string();
  if (dat) spec_.output.deck_dat = stem + ".dat";
  if (frd) spec_.output.deck_frd = stem + ".frd";
}

}  // namespace hencky::inp
