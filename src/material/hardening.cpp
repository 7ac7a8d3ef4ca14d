#include "material/hardening.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>

namespace hencky {

namespace {

using Point = Hardening::Point;
constexpr double inf = std::numeric_limits<double>::infinity();

/// Shortest text that reads back as the same double (as the case reader prints numbers).
std::string num(double v) {
  char buf[64];
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, p) : std::to_string(v);
}

/// A derived value, to 6 significant digits.
std::string g6(double v) {
  return fmt::format("{:.6g}", v);
}

double three_g_of(double E, double nu) {
  return 3 * E / (2 * (1 + nu));
}  // 3G, G = E/(2(1+ν))

/// One table in plastic form: H linear between the breakpoints e[i], constant beyond the last.
struct Piecewise {
  const double* e;
  const double* s;
  const double* k;  // slope of the segment starting at e[i]; k[n-1] = 0
  std::size_t n;

  /// The segment [e[i], e[i+1]) holding p (i = n-1 beyond the last point; p >= 0 = e[0]).
  std::size_t segment(double p) const {
    const std::size_t i = static_cast<std::size_t>(std::upper_bound(e, e + n, p) - e);
    return i == 0 ? 0 : i - 1;
  }
  Point at(double p) const {
    const std::size_t i = segment(p);
    return {s[i] + k[i] * (p - e[i]), k[i]};
  }
};

/// H = (1 − w)·H_a + w·H_b, walked segment by segment over the union of both tables'
/// breakpoints, from ε̃^p = 0: on each segment [p0, p1) H is linear, H(p0) = h0, slope k.
/// Nothing is allocated; the cost is the number of breakpoints passed.
class Walk {
 public:
  Walk(const Piecewise& a, const Piecewise& b, double w) : a_(a), b_(b), w_(w) { set(); }

  /// h1 = H(p1), computed as the next segment's h0 will be: continuity is exact, so that a
  /// value equal to a breakpoint's stress is found at that breakpoint.
  double p0 = 0, p1 = 0, h0 = 0, h1 = 0, k = 0;

  /// The last segment runs to +inf with k = 0 (beyond the last point of both tables).
  bool last() const { return p1 == inf; }
  void next() {
    if (ia_ + 1 < a_.n && a_.e[ia_ + 1] == p1) ++ia_;
    if (ib_ + 1 < b_.n && b_.e[ib_ + 1] == p1) ++ib_;
    p0 = p1;
    set();
  }

 private:
  void set() {
    const double ha = a_.s[ia_] + a_.k[ia_] * (p0 - a_.e[ia_]);
    const double hb = b_.s[ib_] + b_.k[ib_] * (p0 - b_.e[ib_]);
    h0 = (1 - w_) * ha + w_ * hb;
    k = (1 - w_) * a_.k[ia_] + w_ * b_.k[ib_];
    p1 = std::min(ia_ + 1 < a_.n ? a_.e[ia_ + 1] : inf, ib_ + 1 < b_.n ? b_.e[ib_ + 1] : inf);
    if (p1 == inf) {
      h1 = h0;
      return;
    }
    const double ha1 = ia_ + 1 < a_.n && a_.e[ia_ + 1] == p1
                           ? a_.s[ia_ + 1]
                           : a_.s[ia_] + a_.k[ia_] * (p1 - a_.e[ia_]);
    const double hb1 = ib_ + 1 < b_.n && b_.e[ib_ + 1] == p1
                           ? b_.s[ib_ + 1]
                           : b_.s[ib_] + b_.k[ib_] * (p1 - b_.e[ib_]);
    h1 = (1 - w_) * ha1 + w_ * hb1;
  }
  Piecewise a_, b_;
  double w_;
  std::size_t ia_ = 0, ib_ = 0;
};

/// Ramberg-Osgood's plastic strain α(σ_y/E)(σ̃/σ_y)^n.
double ro_plastic(double sigma, double sy, double E, double alpha, double n) {
  return alpha * sy / E * std::pow(sigma / sy, n);
}

/// The location of a table's point i: the strain value in the file when known, reported under
/// the table's key ("materials[0].plasticity.curve.table[1]") so that the message can say
/// "point i".
SourceLocation point_location(const CurveSpec::Table& t, std::size_t j, std::size_t i) {
  SourceLocation w = i < t.point_where.size() ? t.point_where[i] : t.where;
  w.key = t.where.key.empty() ? "plasticity.curve.table[" + std::to_string(j) + "]" : t.where.key;
  return w;
}

SourceLocation property_location(const PropertyTable& p, const SourceLocation& fallback) {
  return p.where.key.empty() && p.where.file.empty() ? fallback : p.where;
}

void check_positive(const PropertyTable& p, const SourceLocation& fallback, const char* what) {
  if (p.value.empty()) throw InputError(fallback, std::string("missing ") + what);
  for (double v : p.value)
    if (!(v > 0) || !std::isfinite(v))
      throw InputError(property_location(p, fallback),
                       std::string(what) + " must be > 0, found " + num(v));
}

/// Temperatures where a property made of linear pieces should be checked: every breakpoint
/// of the tables involved, and points between them (3G = 3E/(2(1+ν)) is not linear in T).
std::vector<double> check_temperatures(std::initializer_list<const PropertyTable*> props) {
  std::vector<double> ts;
  for (const PropertyTable* p : props)
    if (!p->is_constant()) ts.insert(ts.end(), p->temperature.begin(), p->temperature.end());
  std::sort(ts.begin(), ts.end());
  ts.erase(std::unique(ts.begin(), ts.end()), ts.end());
  if (ts.empty()) return {0.0};
  std::vector<double> out;
  for (std::size_t i = 0; i < ts.size(); ++i) {
    out.push_back(ts[i]);
    if (i + 1 < ts.size())
      for (int q = 1; q < 8; ++q) out.push_back(ts[i] + (ts[i + 1] - ts[i]) * q / 8.0);
  }
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Conversion and checks

Hardening::Hardening(const PlasticitySpec& spec, const PropertyTable& E, const PropertyTable& nu)
    : kind_(spec.curve.kind) {
  const CurveSpec& c = spec.curve;
  switch (kind_) {
    case CurveSpec::Kind::table:
      convert_tables(c, E, nu);
      break;
    case CurveSpec::Kind::perfect:
      check_positive(c.yield, c.where, "the yield stress");
      yield_ = c.yield;
      break;
    case CurveSpec::Kind::linear: {
      check_positive(c.yield, c.where, "the yield stress");
      if (c.hardening.value.empty()) throw InputError(c.where, "missing the hardening modulus");
      for (double T : check_temperatures({&c.hardening, &E, &nu})) {
        const double h = c.hardening(T), three_g = three_g_of(E(T), nu(T));
        if (!std::isfinite(h) || h <= -three_g)
          throw InputError(
              property_location(c.hardening, c.where),
              "the hardening modulus dσ/dε^p = " + num(h) + " must be > -3G = " + g6(-three_g) +
                  " (E = " + g6(E(T)) + ", nu = " + g6(nu(T)) +
                  (c.hardening.is_constant() && E.is_constant() && nu.is_constant()
                       ? std::string()
                       : " at temperature " + g6(T)) +
                  "): a curve that falls faster turns back in the strain intensity and has no "
                  "stress for a given strain");
      }
      yield_ = c.yield;
      hardening_ = c.hardening;
      break;
    }
    case CurveSpec::Kind::ramberg_osgood:
      check_positive(c.yield, c.where, "the yield stress");
      if (!(c.ro_E > 0) || !std::isfinite(c.ro_E))
        throw InputError(c.where, "Ramberg-Osgood's E must be > 0, found " + num(c.ro_E));
      if (!(c.ro_alpha > 0) || !std::isfinite(c.ro_alpha))
        throw InputError(c.where, "Ramberg-Osgood's alpha must be > 0, found " + num(c.ro_alpha));
      if (!(c.ro_n > 1) || !std::isfinite(c.ro_n))
        throw InputError(c.where, "Ramberg-Osgood's exponent n must be > 1, found " + num(c.ro_n));
      yield_ = c.yield;
      ro_E_ = c.ro_E;
      ro_alpha_ = c.ro_alpha;
      ro_n_ = c.ro_n;
      break;
  }
}

void Hardening::convert_tables(const CurveSpec& c, const PropertyTable& E,
                               const PropertyTable& nu) {
  if (c.tables.empty()) throw InputError(c.where, "the curve needs at least one table");
  for (std::size_t j = 0; j < c.tables.size(); ++j) {
    const CurveSpec::Table& t = c.tables[j];
    const SourceLocation table_where = point_location(t, j, t.point_where.size());
    if (j > 0 && !(t.temperature > c.tables[j - 1].temperature))
      throw InputError(table_where, "the tables' temperatures must be strictly increasing, found " +
                                        num(t.temperature) + " after " +
                                        num(c.tables[j - 1].temperature));
    if (t.strain.empty() || t.strain.size() != t.stress.size())
      throw InputError(table_where, "expected as many stresses as strains (at least one), found " +
                                        std::to_string(t.strain.size()) + " strains and " +
                                        std::to_string(t.stress.size()) + " stresses");
    const double E_t = E(t.temperature), nu_t = nu(t.temperature);
    const double three_g = three_g_of(E_t, nu_t);
    // The elastic modulus of the table's form: ε^p = ε − σ/E (uniaxial), ε̃^p = ε̃ − σ̃/3G
    // (intensity), at the table's temperature.
    const double modulus = c.form == CurveSpec::Form::uniaxial ? E_t : three_g;
    const std::string at_T = E.is_constant() && nu.is_constant()
                                 ? std::string()
                                 : " at the table's temperature " + num(t.temperature);
    const std::string elastic_line =
        c.form == CurveSpec::Form::uniaxial
            ? "σ = E·ε (E = " + num(E_t) + at_T + ")"
            : "σ̃ = 3G·ε̃ (3G = 3E/(2(1+nu)) = " + g6(three_g) + at_T + ")";
    const char* strain_name = c.form == CurveSpec::Form::uniaxial ? "ε − σ/E" : "ε̃ − σ̃/3G";

    PlasticTable pt;
    pt.temperature = t.temperature;
    for (std::size_t i = 0; i < t.strain.size(); ++i) {
      const double eps = t.strain[i], sig = t.stress[i];
      const SourceLocation where = point_location(t, j, i);
      const std::string point =
          "point " + std::to_string(i) + " (strain " + num(eps) + ", stress " + num(sig) + "): ";
      if (!std::isfinite(eps) || !std::isfinite(sig))
        throw InputError(where, point + "expected finite numbers");
      if (i == 0 && !(sig > 0))
        throw InputError(where, point +
                                    "the first point is the initial yield: its stress must be "
                                    "> 0");
      if (sig < 0) throw InputError(where, point + "stresses must be >= 0");
      double ep = eps;
      if (i == 0) {
        if (c.form == CurveSpec::Form::plastic) {
          if (eps != 0)
            throw InputError(where, point +
                                        "the first point of a plastic-strain table is the "
                                        "initial yield: its strain must be 0");
        } else {
          const double on_line = sig / modulus;
          if (std::abs(eps - on_line) > 1e-3 * on_line)
            throw InputError(
                where, point + "the first point must be the yield point on the elastic line " +
                           elastic_line + ", i.e. strain " + g6(on_line) +
                           " (within 1e-3 relative); add the yield point first if the table "
                           "starts in the plastic range");
        }
        ep = 0;  // on the elastic line within the tolerance: exactly the yield point
      } else {
        if (c.form != CurveSpec::Form::plastic) ep = eps - sig / modulus;
        const double prev = pt.eps_p.back();
        if (!(ep > prev)) {
          if (c.form == CurveSpec::Form::plastic)
            throw InputError(where, point +
                                        "the plastic strain must be strictly increasing, found " +
                                        num(ep) + " after " + num(prev));
          if (!(ep > 0))
            throw InputError(where, point + "the point lies on or left of the elastic line " +
                                        elastic_line + ": its plastic strain " + strain_name +
                                        " = " + g6(ep) + " is not > 0");
          throw InputError(where, point + "its plastic strain " + strain_name + " = " + g6(ep) +
                                      " does not increase from the previous point's " + g6(prev) +
                                      "; from one point to the next the stress may not rise "
                                      "faster than along the elastic line " +
                                      elastic_line);
        }
        const double slope = (sig - pt.stress.back()) / (ep - prev);
        if (!(slope > -three_g))
          throw InputError(where, point + "the curve falls too steeply: dσ̃/dε̃^p = " + g6(slope) +
                                      " must be > -3G = " + g6(-three_g) + " (E = " + num(E_t) +
                                      ", nu = " + num(nu_t) + at_T +
                                      "); it would turn back in the strain intensity and have no "
                                      "stress for a given strain");
      }
      pt.eps_p.push_back(ep);
      pt.stress.push_back(sig);
    }
    pt.slope.assign(pt.eps_p.size(), 0.0);
    for (std::size_t i = 0; i + 1 < pt.eps_p.size(); ++i)
      pt.slope[i] = (pt.stress[i + 1] - pt.stress[i]) / (pt.eps_p[i + 1] - pt.eps_p[i]);
    table_end_ = std::max(table_end_, pt.eps_p.back());
    tables_.push_back(std::move(pt));
  }
}

// ---------------------------------------------------------------------------------------------
// Evaluations

Hardening::Bracket Hardening::bracket(double T) const {
  const std::size_t n = tables_.size();
  if (n == 1 || !(T > tables_.front().temperature)) return {0, 0, 0.0};
  if (T >= tables_.back().temperature) return {n - 1, n - 1, 0.0};
  std::size_t b = 1;
  while (tables_[b].temperature <= T) ++b;  // few tables: a linear search
  const double Ta = tables_[b - 1].temperature, Tb = tables_[b].temperature;
  return {b - 1, b, (T - Ta) / (Tb - Ta)};
}

namespace {
Piecewise piece(const std::vector<double>& e, const std::vector<double>& s,
                const std::vector<double>& k) {
  return {e.data(), s.data(), k.data(), e.size()};
}

/// The walk over the mix (1 − s)·a + s·b of two plastic tables (Hardening::PlasticTable: the
/// template only names the private type through deduction).
template <class Table>
Walk table_walk(const Table& a, const Table& b, double s) {
  return Walk(piece(a.eps_p, a.stress, a.slope), piece(b.eps_p, b.stress, b.slope), s);
}
}  // namespace

Hardening::Point Hardening::plastic(double eps_p, double T) const {
  const double p = std::max(eps_p, 0.0);
  switch (kind_) {
    case CurveSpec::Kind::table: {
      const Bracket br = bracket(T);
      const PlasticTable& a = tables_[br.a];
      const Point ha = piece(a.eps_p, a.stress, a.slope).at(p);
      if (br.s == 0) return ha;
      const PlasticTable& b = tables_[br.b];
      const Point hb = piece(b.eps_p, b.stress, b.slope).at(p);
      return {(1 - br.s) * ha.value + br.s * hb.value, (1 - br.s) * ha.slope + br.s * hb.slope};
    }
    case CurveSpec::Kind::perfect:
      return {yield_(T), 0.0};
    case CurveSpec::Kind::linear: {
      const double h = hardening_(T), v = yield_(T) + h * p;
      if (h < 0 && v <= 0) return {0.0, 0.0};  // softened to zero stress: stays there
      return {v, h};
    }
    case CurveSpec::Kind::ramberg_osgood: {
      if (p == 0) return {0.0, inf};
      const double sy = yield_(T);
      // ε̃^p = α(σ_y/E)(H/σ_y)^n solved for H
      const double v = sy * std::pow(p * ro_E_ / (ro_alpha_ * sy), 1 / ro_n_);
      return {v, v / (ro_n_ * p)};
    }
  }
  return {};
}

Hardening::Point Hardening::phi(double eps, double T, double three_g) const {
  const Point elastic{three_g * eps, three_g};
  if (!(eps > 0)) return elastic;
  switch (kind_) {
    case CurveSpec::Kind::table: {
      const Bracket br = bracket(T);
      Walk w = table_walk(tables_[br.a], tables_[br.b], br.s);
      if (eps < w.h0 / three_g) return elastic;
      // ε̃ = g(ε̃^p) = ε̃^p + H(ε̃^p)/3G is linear on each segment: the first segment whose
      // end lies beyond ε̃ holds the root (taken at the start of the next segment when ε̃ is
      // exactly at a breakpoint, so that the slope is the one to the right).
      for (;; w.next()) {
        const double d = 1 + w.k / three_g;  // dg/dε̃^p on this segment
        if (w.last() || (d > 0 && eps < w.p1 + w.h1 / three_g)) {
          const double g0 = w.p0 + w.h0 / three_g;
          const double p = w.p0 + (eps - g0) / d;
          return {w.h0 + w.k * (p - w.p0), three_g * w.k / (three_g + w.k)};
        }
      }
    }
    case CurveSpec::Kind::perfect: {
      const double y = yield_(T);
      if (eps < y / three_g) return elastic;
      return {y, 0.0};
    }
    case CurveSpec::Kind::linear: {
      const double y = yield_(T), h = hardening_(T);
      if (eps < y / three_g) return elastic;
      const double p = (eps - y / three_g) / (1 + h / three_g);
      const double v = y + h * p;
      if (h < 0 && v <= 0) return {0.0, 0.0};
      return {v, three_g * h / (three_g + h)};
    }
    case CurveSpec::Kind::ramberg_osgood: {
      // Solve r(σ̃) = σ̃/3G + ε̃^p(σ̃) − ε̃ = 0, increasing and convex in σ̃ > 0: Newton from an
      // upper bound descends monotonically to the root; a bracket guards against round-off.
      const double sy = yield_(T), n = ro_n_;
      double hi = std::min(three_g * eps, sy * std::pow(eps * ro_E_ / (ro_alpha_ * sy), 1 / n));
      double lo = 0, s = hi;
      for (int it = 0; it < 200; ++it) {
        const double ep = ro_plastic(s, sy, ro_E_, ro_alpha_, n);
        const double r = s / three_g + ep - eps;
        if (r == 0) break;
        (r > 0 ? hi : lo) = s;
        double next = s - r / (1 / three_g + n * ep / s);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        const bool done = std::abs(next - s) <= 1e-15 * s;
        s = next;
        if (done) break;
      }
      const double ep = ro_plastic(s, sy, ro_E_, ro_alpha_, n);
      return {s, 1 / (1 / three_g + n * ep / s)};  // 3G·H'/(3G + H')
    }
  }
  return elastic;
}

Hardening::Point Hardening::f(double sigma, double T, double three_g) const {
  const Point elastic{sigma / three_g, 1 / three_g};
  const Point beyond{inf, inf};
  if (!(sigma > 0)) return elastic;
  switch (kind_) {
    case CurveSpec::Kind::table: {
      const Bracket br = bracket(T);
      Walk w = table_walk(tables_[br.a], tables_[br.b], br.s);
      if (sigma < w.h0) return elastic;
      // The first ε̃^p where H reaches σ̃: on a rising segment with h0 <= σ̃ <= h1 (h0 < σ̃ on
      // every segment after the first, or the previous one would have held it).
      for (; !w.last(); w.next()) {
        if (sigma == w.h0) {  // at a breakpoint (or the yield point): slope to the right
          return {sigma / three_g + w.p0, w.k > 0 ? 1 / three_g + 1 / w.k : inf};
        }
        if (w.k > 0 && sigma < w.h1) {
          const double p = w.p0 + (sigma - w.h0) / w.k;
          return {sigma / three_g + p, 1 / three_g + 1 / w.k};
        }
        if (w.k > 0 && sigma == w.h1) continue;  // the next segment starts at σ̃
      }
      if (sigma == w.h0) return {sigma / three_g + w.p0, inf};  // the flat end's stress
      return beyond;
    }
    case CurveSpec::Kind::perfect: {
      const double y = yield_(T);
      if (sigma < y) return elastic;
      return sigma == y ? Point{sigma / three_g, inf} : beyond;
    }
    case CurveSpec::Kind::linear: {
      const double y = yield_(T), h = hardening_(T);
      if (sigma < y) return elastic;
      if (h > 0) return {sigma / three_g + (sigma - y) / h, 1 / three_g + 1 / h};
      return sigma == y ? Point{sigma / three_g, inf} : beyond;
    }
    case CurveSpec::Kind::ramberg_osgood: {
      const double sy = yield_(T);
      const double ep = ro_plastic(sigma, sy, ro_E_, ro_alpha_, ro_n_);
      return {sigma / three_g + ep, 1 / three_g + ro_n_ * ep / sigma};
    }
  }
  return elastic;
}

double Hardening::max_stress(double T) const {
  switch (kind_) {
    case CurveSpec::Kind::table: {
      const Bracket br = bracket(T);
      Walk w = table_walk(tables_[br.a], tables_[br.b], br.s);
      double m = w.h0;
      for (; !w.last(); w.next()) m = std::max(m, w.h1);
      return m;
    }
    case CurveSpec::Kind::perfect:
      return yield_(T);
    case CurveSpec::Kind::linear:
      return hardening_(T) > 0 ? inf : yield_(T);
    case CurveSpec::Kind::ramberg_osgood:
      return inf;
  }
  return inf;
}

void Hardening::warn_outside(const std::string& material, double T_min, double T_max,
                             double eps_p_max, Log& log) const {
  if (kind_ == CurveSpec::Kind::table) {
    // One table: the curve does not depend on temperature, nothing to leave.
    const double lo = tables_.front().temperature, hi = tables_.back().temperature;
    if (tables_.size() > 1 && leaves_range(T_min, T_max, lo, hi))
      log.warn_once("hardening-temperature:" + material,
                    fmt::format("material '{}': temperatures {:g} .. {:g} at integration points "
                                "leave the hardening curve's tables ({:g} .. {:g}); the table at "
                                "the nearest end is used outside them (warned once)",
                                material, T_min, T_max, lo, hi));
    // The tables in use over [T_min, T_max]; each is flat beyond its last point. Tables of a
    // single point are perfectly plastic on purpose: no warning for them.
    const std::size_t first = bracket(T_min).a, last = bracket(T_max).b;
    double end = inf, end_T = 0;
    for (std::size_t j = first; j <= last && j < tables_.size(); ++j)
      if (tables_[j].eps_p.size() > 1 && tables_[j].eps_p.back() < end) {
        end = tables_[j].eps_p.back();
        end_T = tables_[j].temperature;
      }
    if (eps_p_max > end)
      log.warn_once(
          "hardening-strain:" + material,
          fmt::format("material '{}': the equivalent plastic strain reached {:g}, beyond the last "
                      "point of its hardening curve ({:g}{}); the stress stays at the last value "
                      "there, as for perfect plasticity (warned once)",
                      material, eps_p_max, end,
                      tables_.size() > 1 ? fmt::format(" in the table at {:g}", end_T) : ""));
    return;
  }
  for (const PropertyTable* p : {&yield_, &hardening_}) {
    if (p->left_by(T_min, T_max))
      log.warn_once("hardening-temperature:" + material + ":" + p->where.key,
                    fmt::format("material '{}': the integration points' temperatures, {:.6g} .. "
                                "{:.6g}, reach outside the table of '{}' ({:.6g} .. {:.6g}); "
                                "its end values are used there (warned once)",
                                material, T_min, T_max, p->where.key, p->temperature.front(),
                                p->temperature.back()));
  }
}

}  // namespace hencky
