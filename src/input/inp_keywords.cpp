// The keywords of a deck read into InpReader's nodes, elements, sets and surfaces
// (input/inp_parser.hpp). The keywords as the Abaqus Keywords Reference Guide and the CalculiX
// User's Manual (ccx 2.20, section 6: *NODE, *ELEMENT, *NSET, *ELSET, *SURFACE, *INCLUDE)
// define them.
#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>

#include "input/inp_parser.hpp"

namespace hencky::inp {

Mesh InpReader::read() {
  const auto& lines = deck_.lines;
  std::size_t i = 0;
  while (i < lines.size()) {
    if (lines[i].text.front() != '*')
      throw fail(static_cast<int>(i), "a data line before any keyword");
    const int at = static_cast<int>(i);
    const Keyword k = parse_keyword(lines[i].text);
    std::size_t end = i + 1;
    while (end < lines.size() && lines[end].text.front() != '*') ++end;
    keyword(k, at, static_cast<int>(i + 1), static_cast<int>(end));
    i = end;
  }
  if (history_) history_->finish(*this);
  return build();
}

long InpReader::label(std::string_view s, int line, const char* what) const {
  long v = 0;
  const char* b = s.data();
  const char* e = b + s.size();
  if (b != e && *b == '+') ++b;
  const auto [p, ec] = std::from_chars(b, e, v);
  if (ec != std::errc() || p != e || v <= 0)
    throw fail(line, fmt::format("expected a {} (a positive whole number), found '{}'", what, s));
  return v;
}

double InpReader::real(std::string_view s, int line, const char* what) const {
  std::string t;  // only for Fortran's 1.0D+03: the usual number is parsed where it is
  if (s.find_first_of("dD") != std::string_view::npos) {
    t = s;
    for (char& c : t)
      if (c == 'd' || c == 'D') c = 'e';
  }
  const char* b = t.empty() ? s.data() : t.data();
  const char* e = b + (t.empty() ? s.size() : t.size());
  if (b != e && *b == '+') ++b;
  double v = 0;
  const auto [p, ec] = std::from_chars(b, e, v);
  if (ec != std::errc() || p != e || !std::isfinite(v))
    throw fail(line, fmt::format("expected a {} (a finite number), found '{}'", what, s));
  return v;
}

void InpReader::keyword(const Keyword& k, int at, int first, int end) {
  if (k.name.empty()) throw fail(at, "a keyword line without a keyword ('*' alone)");
  if (k.name == "HEADING" && !history_) return;
  if (k.name == "PART") return part(k, at);
  if (k.name == "END PART" || k.name == "END INSTANCE") {
    in_instance_ = false;
    return;
  }
  if (k.name == "ASSEMBLY") {
    in_assembly_ = true;
    return;
  }
  if (k.name == "END ASSEMBLY") {
    in_assembly_ = false;
    return;
  }
  if (k.name == "INSTANCE") return instance(k, at, first, end);
  // Nodes, elements and sets of the assembly itself (outside its instance) are reference
  // points and their sets, not the body.
  const bool of_assembly = in_assembly_ && !in_instance_ && !k.has("INSTANCE");
  if (k.name == "NODE" || k.name == "ELEMENT" || k.name == "NSET" || k.name == "ELSET") {
    if (k.has("INPUT"))
      throw fail(at, "*" + k.name +
                         ", INPUT=... is not read; write *INCLUDE, INPUT=... "
                         "around the data lines instead");
    if (of_assembly) {
      skip("*" + k.name + " of the assembly (reference points)", at);
      return;
    }
  }
  if (k.name == "NODE") return nodes(k, at, first, end);
  if (k.name == "ELEMENT") return elements(k, at, first, end);
  if (k.name == "NSET") return set(k, at, first, end, true);
  if (k.name == "ELSET") return set(k, at, first, end, false);
  if (k.name == "SURFACE") return surface(k, at, first, end);
  if (history_) return history_->keyword(*this, k, at, first, end);
  skip("*" + k.name, at);
}

void InpReader::skip(const std::string& what, int at) {
  const std::pair<int, std::string> item{deck_.lines[at].file, what};
  if (std::find(skipped_.begin(), skipped_.end(), item) == skipped_.end()) skipped_.push_back(item);
}

void InpReader::part(const Keyword& k, int at) {
  const std::string* name = k.get("NAME");
  const std::string n = name ? *name : "";
  if (!part_name_.empty())
    throw fail(at, fmt::format("a second *PART ('{}' after '{}'): hencky reads a deck of one "
                               "part (write the model as one part, or without parts)",
                               n, part_name_));
  part_name_ = n.empty() ? "(unnamed)" : n;
}

void InpReader::instance(const Keyword& k, int at, int first, int end) {
  const std::string* name = k.get("NAME");
  if (++instances_ > 1)
    throw fail(at, fmt::format("a second *INSTANCE ('{}'): hencky reads a deck of one part "
                               "with at most one instance of it",
                               name ? *name : ""));
  if (first < end)
    throw fail(first,
               "the instance is moved (translation or rotation lines): hencky reads the "
               "part where its nodes are; write the deck without the move");
  in_instance_ = true;
}

void InpReader::nodes(const Keyword& k, int at, int first, int end) {
  if (const std::string* sys = k.get("SYSTEM"); sys && upper(*sys) != "R")
    throw fail(at,
               "*NODE, SYSTEM=" + *sys + ": hencky reads rectangular coordinates only (SYSTEM=R)");
  const std::string* nset = k.get("NSET");
  Set* s = nset ? &open_set(nsets_, *nset, at) : nullptr;
  for (int l = first; l < end; ++l) {
    const auto f = data(l);
    if (f.empty()) continue;
    if (f.size() > 4)
      throw fail(l, fmt::format("a node line is 'label, x, y, z'; found {} fields", f.size()));
    const long n = label(f[0], l, "node label");
    double x[3] = {0, 0, 0};
    for (std::size_t d = 1; d < f.size(); ++d) x[d - 1] = real(f[d], l);
    const auto [it, fresh] = node_of_label_.emplace(n, static_cast<int>(node_label_.size()));
    if (!fresh)
      throw fail(l, fmt::format("node {} is defined twice (first on line {})", n,
                                deck_.lines[node_line_[it->second]].number));
    node_label_.push_back(n);
    node_line_.push_back(l);
    xyz_.insert(xyz_.end(), x, x + 3);
    if (s) add_member(*s, {n, n, 1, l});
  }
}

void InpReader::elements(const Keyword& k, int at, int first, int end) {
  const std::string* t = k.get("TYPE");
  if (!t || t->empty()) throw fail(at, "*ELEMENT needs TYPE=<element type>, e.g. TYPE=C3D10");
  const std::string type = upper(*t);
  const auto kind = element_kind(type);
  if (const auto* why = std::get_if<std::string>(&kind)) throw fail(at, *why);
  const ElementKind ek = std::get<ElementKind>(kind);
  const std::string* elset = k.get("ELSET");
  Set* s = elset ? &open_set(elsets_, *elset, at) : nullptr;
  // An element's labels may go on over several lines (Abaqus: a line ends with a comma;
  // CalculiX reads on until the type's node count, comma or not): read until the count.
  const std::size_t want = ek.nodes > 0 ? static_cast<std::size_t>(ek.nodes) + 1 : 0;
  std::vector<long> labels;
  int start = first;
  for (int l = first; l < end; ++l) {
    if (labels.empty()) start = l;
    for (auto v : data(l)) labels.push_back(label(v, l, "label"));
    if (labels.empty()) continue;
    if (want == 0 ? text(l).back() == ',' : labels.size() < want) {
      if (l + 1 < end) continue;
      throw fail(l, fmt::format("element {} has {} nodes, and {} has {}: the element's "
                                "line ends the data (is the file cut short?)",
                                labels[0], labels.size() - 1, type, ek.nodes));
    }
    if (want > 0 && labels.size() > want) {
      // More numbers than the type has nodes: ccx takes the first (decks of its test suite,
      // beampsensfreq and dloadlinI, carry 10 on C3D8 lines); a warning says so.
      if (extra_numbers_.first++ == 0) extra_numbers_.second = l;
      labels.resize(want);
    }
    add_element(type, ek, labels, start);
    if (s) add_member(*s, {labels[0], labels[0], 1, start});
    labels.clear();
  }
}

void InpReader::add_element(const std::string& type, const ElementKind& ek,
                            const std::vector<long>& labels, int line) {
  const long e = labels[0];
  if (element_of_label_.count(e) || skipped_elements_.count(e)) {
    const int before = element_of_label_.count(e) ? elements_[element_of_label_.at(e)].line
                                                  : skipped_elements_.at(e);
    throw fail(line, fmt::format("element {} is defined twice (first on line {})", e,
                                 deck_.lines[before].number));
  }
  if (ek.kind == ElementKind::Kind::skipped) {
    skipped_elements_.emplace(e, line);
    ++skipped_types_[type];
    return;
  }
  if (type != "C3D4" && type != "C3D10" && type != "C3D8" && type != "C3D20" && type != "C3D6" &&
      ek.kind == ElementKind::Kind::volume)
    ++renamed_types_[type];
  else if (type == "C3D8" || type == "C3D6" || (type == "C3D20" && !history_))
    ++convention_types_[type];
  if (ek.kind == ElementKind::Kind::volume) ++volume_types_[type];
  element_of_label_.emplace(e, static_cast<int>(elements_.size()));
  elements_.push_back({e, ek, type, static_cast<int>(conn_.size()), line});
  conn_.insert(conn_.end(), labels.begin() + 1, labels.end());
}

Set& InpReader::open_set(std::map<std::string, Set>& sets, const std::string& name, int at) {
  if (name.empty()) throw fail(at, "a set without a name");
  auto [it, fresh] = sets.try_emplace(upper(name));
  if (fresh) {
    it->second.name = name;
    it->second.line = at;
    (&sets == &nsets_ ? nset_order_ : elset_order_).push_back(it->first);
  }
  return it->second;
}

void InpReader::add_member(Set& s, const Member& m) {
  const std::size_t n = static_cast<std::size_t>(m.count());
  s.count += n;
  total_members_ += n;
  if (total_members_ > max_members)
    throw fail(m.line, fmt::format("the sets hold more than {} labels", max_members));
  s.members.push_back(m);
}

void InpReader::set(const Keyword& k, int at, int first, int end, bool of_nodes) {
  const char* kind = of_nodes ? "NSET" : "ELSET";
  const std::string* name = k.get(kind);
  if (!name) throw fail(at, fmt::format("*{} needs {}=<name>", kind, kind));
  auto& sets = of_nodes ? nsets_ : elsets_;
  Set& s = open_set(sets, *name, at);
  s.internal = s.internal || k.has("INTERNAL");
  const bool generate = k.has("GENERATE");
  const bool of_elsets = of_nodes && k.has("ELSET");  // *NSET, ELSET: nodes of element sets
  for (int l = first; l < end; ++l) {
    const auto f = data(l);
    if (generate) {
      if (f.size() < 2 || f.size() > 3)
        throw fail(l, "a GENERATE line is 'first, last' or 'first, last, step'");
      Member m{label(f[0], l, "label"), label(f[1], l, "label"),
               f.size() == 3 ? label(f[2], l, "step") : 1, l, true};
      if (m.last < m.first)
        throw fail(l, fmt::format("GENERATE from {} down to {}", m.first, m.last));
      add_member(s, m);
      continue;
    }
    for (auto v : f) {
      if (of_elsets) {
        each_label(find_set(elsets_, v, l, "ELSET"), [&](long el, int) {
          auto it = element_of_label_.find(el);
          if (it == element_of_label_.end()) return;  // checked where the ELSET is used
          const Element& x = elements_[it->second];
          for (int a = 0; a < x.kind.nodes; ++a) {
            const long n = conn_[x.offset + a];
            add_member(s, {n, n, 1, l, false});
          }
        });
      } else if (is_label(v)) {
        const long n = label(v, l, of_nodes ? "node label" : "element label");
        add_member(s, {n, n, 1, l, false});
      } else {
        const Set& other = find_set(sets, v, l, kind);
        // A copy, as the set is when named: a later addition to it does not count here.
        const std::vector<Member> copy = other.members;
        for (const Member& m : copy) add_member(s, m);
      }
    }
  }
}

const Set& InpReader::find_set(const std::map<std::string, Set>& sets, std::string_view name,
                               int line, const char* kind) const {
  const auto it = sets.find(upper(unquote(name)));
  if (it == sets.end())
    throw fail(line, fmt::format("'{}' is neither a label nor an {} defined before this line", name,
                                 kind));
  return it->second;
}

void InpReader::surface(const Keyword& k, int at, int first, int end) {
  const std::string* name = k.get("NAME");
  if (!name || name->empty()) throw fail(at, "*SURFACE needs NAME=<name>");
  const std::string* type = k.get("TYPE");
  const std::string t = type ? upper(*type) : "ELEMENT";
  if (t != "ELEMENT" && t != "NODE")
    throw fail(at, "*SURFACE, TYPE=" + *type +
                       ": hencky reads element-based (TYPE=ELEMENT) and node-based (TYPE=NODE) "
                       "surfaces");
  // A node-based and an element-based surface may share a name: two surfaces, a region of
  // nodes and one of faces of that name.
  auto [it, fresh] = surfaces_.try_emplace(SurfaceKey{upper(*name), t == "NODE"});
  Surface& s = it->second;
  if (fresh) {
    s.name = *name;
    s.nodes = t == "NODE";
    s.line = at;
    surface_order_.push_back(it->first);
  }
  for (int l = first; l < end; ++l) {
    const auto f = data(l);
    if (f.empty()) continue;
    SurfaceItem item;
    item.line = l;
    if (is_label(f[0]))
      item.label = label(f[0], l, s.nodes ? "node label" : "element label");
    else
      item.set = upper(unquote(f[0]));
    if (!s.nodes && !(f.size() == 1 && !item.set.empty())) {  // an ELSET alone: its exterior
      const std::string face = f.size() > 1 ? upper(f[1]) : "";
      if (face.size() != 2 || face[0] != 'S' || face[1] < '1' || face[1] > '6')
        throw fail(l, fmt::format("an element-based surface line is 'element or ELSET, face' "
                                  "with the face S1 .. S6; found '{}'",
                                  text(l)));
      item.side = face[1] - '0';
    }
    s.items.push_back(std::move(item));
  }
}

std::vector<long> InpReader::node_targets(std::string_view target, int line) const {
  std::vector<long> labels;
  if (is_label(target)) {
    const long n = label(target, line, "node label");
    if (!node_of_label_.count(n))
      throw fail(line, fmt::format("node {} is not defined by a *NODE", n));
    labels.push_back(n);
    return labels;
  }
  return set_nodes(find_set(nsets_, target, line, "NSET"));
}

std::vector<long> InpReader::set_nodes(const Set& s, long* gaps) const {
  std::vector<long> labels;
  for (const Member& m : s.members)
    for (long k = 0, count = m.count(); k < count; ++k) {
      const long n = m.label(k);
      if (node_of_label_.count(n)) {
        labels.push_back(n);
      } else if (m.generated) {
        if (gaps) ++*gaps;
      } else {
        throw fail(m.line,
                   fmt::format("NSET '{}' names node {}, which no *NODE defines", s.name, n));
      }
    }
  return labels;
}

std::vector<long> InpReader::body_node_labels() const {
  std::vector<long> nodes;
  for (const Element& e : elements_)
    if (e.kind.kind == ElementKind::Kind::volume)
      nodes.insert(nodes.end(), conn_.begin() + e.offset, conn_.begin() + e.offset + e.kind.nodes);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

bool InpReader::covers_body(const std::vector<long>& labels) const {
  std::vector<long> volume;
  for (long e : labels) {
    const auto it = element_of_label_.find(e);
    if (it != element_of_label_.end() &&
        elements_[it->second].kind.kind == ElementKind::Kind::volume)
      volume.push_back(e);
  }
  std::sort(volume.begin(), volume.end());
  const auto unique = std::unique(volume.begin(), volume.end()) - volume.begin();
  long body = 0;
  for (const auto& [type, n] : volume_types_) body += n;
  return unique == body;
}

std::vector<long> InpReader::element_targets(std::string_view target, int line) const {
  std::vector<long> labels;
  if (is_label(target)) {
    labels.push_back(label(target, line, "element label"));
    return labels;
  }
  each_label(find_set(elsets_, target, line, "ELSET"), [&](long e, int) { labels.push_back(e); });
  return labels;
}

std::vector<ElementFace> InpReader::face_targets(std::string_view target, int side, int line) {
  std::vector<ElementFace> faces;
  if (side > 0) {
    for (long e : element_targets(target, line)) faces.emplace_back(e, side);
    return faces;
  }
  const auto it = surfaces_.find(SurfaceKey{upper(unquote(target)), false});
  if (it == surfaces_.end())
    throw fail(line, fmt::format("'{}' is not an element-based *SURFACE defined before this line",
                                 target));
  for (const SurfaceItem& item : it->second.items) {
    if (item.set.empty()) {
      faces.emplace_back(item.label, item.side);
      continue;
    }
    for (long e : element_targets(item.set, item.line)) {
      if (item.side > 0) {
        faces.emplace_back(e, item.side);
        continue;
      }
      const auto el = element_of_label_.find(e);  // the set's faces on the body's outside
      if (el == element_of_label_.end() ||
          elements_[el->second].kind.kind != ElementKind::Kind::volume)
        continue;
      const Element& x = elements_[el->second];
      for (int k = 1;; ++k) {
        const std::span<const int> face = abaqus_face(x.kind.type, k);
        if (face.empty()) break;
        if (face_count().at(face_key(x, face)) == 1) faces.emplace_back(e, k);
      }
    }
  }
  return faces;
}

void InpReader::add_node_set(const std::string& name, const std::vector<long>& labels, int line) {
  Set& s = open_set(nsets_, name, line);
  for (long n : labels) add_member(s, {n, n, 1, line, false});
}

void InpReader::add_face_surface(const std::string& name, const std::vector<ElementFace>& faces,
                                 int line) {
  auto [it, fresh] = surfaces_.try_emplace(SurfaceKey{upper(name), false});
  if (fresh) {
    it->second.name = name;
    it->second.line = line;
    surface_order_.push_back(it->first);
  }
  for (const auto& [e, side] : faces) it->second.items.push_back({"", e, side, line});
}

}  // namespace hencky::inp
