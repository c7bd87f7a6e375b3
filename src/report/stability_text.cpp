/// The stability part's sentences (stability_text.h). The predictions are derived in the comments
/// of predict() and in docs/stability.md.
#include "report/stability_text.h"

#include <fmt/core.h>

#include <algorithm>
#include <limits>
#include <map>

namespace rayproof::report {

namespace {

/// Built-in methods that intersect a triangle through a transform precomputed from the absolute
/// vertex positions (instead of differences of the inputs).
bool absolute_positions(const std::string& m) { return m == "baldwin-weber"; }
/// Built-in methods whose sphere test takes the discriminant from the perpendicular vector
/// (Ray Tracing Gems ch. 7) instead of b^2 - a c.
bool stable_quadric(const std::string& m) { return m == "robust" || m == "robust-double"; }

int ceil_div3(int x) { return x >= 0 ? (x + 2) / 3 : -((-x) / 3); }
int floor_div3(int x) { return x >= 0 ? x / 3 : -((-x + 2) / 3); }

/// Sweep direction: +1 when the knob's exponents increase with stiffness, -1 when they decrease.
int direction(const gen::Knob& k) {
  return k.exponents.size() > 1 && k.exponents.back() < k.exponents.front() ? -1 : 1;
}

const char* verdict_text(Agreement a) {
  switch (a) {
    case Agreement::as_predicted: return "as predicted";
    case Agreement::earlier: return "earlier";
    case Agreement::later: return "later";
  }
  return "";
}

/// A reason for a disagreement, when one is known from the numbers alone; else "".
std::string reason(const gen::Knob& k, const verify::StabilityCurve& c, const verify::Break& b, Agreement a) {
  const int in_bits = c.precision == Precision::float32 ? 24 : 53;
  if (k.name == "tilt_plane" && a == Agreement::later)
    return fmt::format("past about 2^-{} its {}-bit input rounds the tilt away (the ray becomes exactly parallel), so only "
                       "the steps before that could show it",
                       in_bits, in_bits);
  if (a == Agreement::as_predicted || !b.class_errors) return "";
  const int e = *b.class_errors;
  if (k.name == "tangency" && a == Agreement::earlier && e <= -in_bits)
    return fmt::format("past 2^-{} its {}-bit input cannot hold the gap: R (1 + 2^k) rounds to R, an exact tangent",
                       in_bits, in_bits);
  if (k.name == "offset" && a == Agreement::earlier && e > in_bits - 13) {
    // The lattice values reach 2^12 (vertices) beside an offset of 2^(k+12): a p-bit input holds
    // them exactly only while k + 13 <= p.
    std::size_t errors = 0, n = 0;
    for (const auto& st : c.steps)
      if (st.exponent == e) errors = st.stats.class_errors(), n = st.stats.cases;
    return fmt::format("past 2^{} its {}-bit input rounds the case's lattice beside the offset, so it sees a coarser "
                       "case, not the translated one ({} of {} cases)",
                       in_bits - 13, in_bits, errors, n);
  }
  if ((k.name == "magnitude_large" || k.name == "magnitude_small") && a == Agreement::earlier) {
    // The same window for a product of four coordinates (watertight's scaled differences).
    const int bits = arithmetic_bits(c.method, c.precision, k.kind);
    const int top = bits == 24 ? 128 : 1024, normal = bits == 24 ? -126 : -1022, sub = bits == 24 ? -149 : -1074;
    Prediction four;
    if (k.name == "magnitude_large") four.mild = (top - 32) / 4, four.stiff = top / 4;
    else four.mild = normal / 4, four.stiff = (sub - 32) / 4;
    if (agreement(k, c, b, four) == Agreement::as_predicted)
      return fmt::format("as for a product of four coordinates ({} .. {})", pow2_text(four.mild), pow2_text(four.stiff));
  }
  return "";
}

}  // namespace

std::string pow2_text(int exponent) { return fmt::format("2^{}", exponent); }

int arithmetic_bits(const std::string& method, Precision inputs, io::Kind kind) {
  if (method == "mt-double") return 53;
  if (method == "robust" && kind == io::Kind::triangle) return 53;
  return inputs == Precision::float32 ? 24 : 53;
}

std::optional<Prediction> predict(const gen::Knob& knob, const std::string& method, Precision inputs,
                                  const Promise& promise) {
  Prediction p;
  if (promise.exact_class) {
    p.never = true;
    p.why = "promises the exact class";
    return p;
  }
  const int bits = arithmetic_bits(method, inputs, knob.kind);
  const std::string arith = fmt::format("{}-bit arithmetic", bits);
  if (knob.name == "tilt_triangle") {
    // det = e1 . (d x e2) = d . (e1 x e2) is about 2^k |e1 x e2| |d| n_z / |n|, computed from
    // products as large as |e1| |e2| |d|; its rounding error, a few 2^-p of those, swamps it when
    // 2^k is 2^-p times the slant |n| / n_z (up to 2^4 here) and the shape factor |e1||e2| / |e1 x e2|
    // (typically up to 2^4; thinner lattice triangles exist): the first class errors between
    // 2^-(p-8) and 2^-p.
    p.mild = -(bits - 8), p.stiff = -bits;
    p.why = arith + ": the determinant n . d is 2^k times its terms (up to the normal's slant and the "
                    "triangle's shape, typically 2^8 together) and is rounded at 2^-p of them";
    return p;
  }
  if (knob.name == "tilt_plane") {
    // n . d is 2^k |n||d| within a factor 4 (the knob's definition) and is computed with a rounding
    // error of a few 2^-p |n||d|: class errors start within a factor 4 of 2^-p either way.
    p.mild = -(bits - 4), p.stiff = -(bits + 2);
    p.why = arith + ": n . d is 2^k |n||d| within a factor 4, rounded at 2^-p |n||d|";
    return p;
  }
  if (knob.name == "offset") {
    if (absolute_positions(method)) {
      // Its transform holds n . v0 and the like, about 2^-p of the offset off: the hit point is
      // off by 2^-p of the offset, and these hits are at least 2^-8 of the size from an edge.
      p.mild = 0, p.stiff = bits - 8;
      p.why = arith + " on absolute positions: an error of 2^-p of the offset reaches the hits' margin of 2^-8 "
                      "of the size by an offset of 2^(p-8)";
    } else {
      // Origin and vertices are all near the same offset: their differences are exact (Sterbenz),
      // so after them the case is the untranslated one.
      p.never = true;
      p.why = arith + " on differences of the inputs: they are exact at any offset (Sterbenz)";
    }
    return p;
  }
  if (knob.name == "magnitude_large" || knob.name == "magnitude_small") {
    // A determinant is a product of three coordinates of 2^k to 2^(k+8) (the lattice's integers):
    // it overflows past 2^E (E = 128 or 1024) for k between (E - 24) / 3 and E / 3, and loses bits
    // below 2^-126 (2^-1022) to vanish below 2^-149 (2^-1074), for k between -126 / 3 and
    // (-149 - 24) / 3. Float inputs themselves stop at float's range, beyond which a 53-bit
    // computation cannot be reached.
    const bool large = knob.name == "magnitude_large";
    const bool float_inputs = inputs == Precision::float32;
    if (bits == 53 && float_inputs) {
      p.never = true;
      p.why = arith + " on float inputs: the inputs leave float's range before a 53-bit product does";
      return p;
    }
    const int top = bits == 24 ? 128 : 1024, normal = bits == 24 ? -126 : -1022, sub = bits == 24 ? -149 : -1074;
    if (large) p.mild = floor_div3(top - 24), p.stiff = ceil_div3(top);
    else p.mild = ceil_div3(normal), p.stiff = floor_div3(sub - 24);
    p.why = arith + (large ? fmt::format(": a product of three coordinates overflows past 2^{}", top)
                           : fmt::format(": a product of three coordinates goes subnormal below 2^{} and to zero below 2^{}",
                                         normal, sub));
    return p;
  }
  if (knob.name == "tangency") {
    if (stable_quadric(method)) {
      // The perpendicular vector (o - C) - ((o - C) . d / |d|^2) d is exact on these axis-aligned
      // rays, so R^2 - |f|^2 is exact in the arithmetic.
      p.never = true;
      p.why = arith + ", discriminant from the perpendicular vector: exact on these axis-aligned rays";
      return p;
    }
    // c = |o - C|^2 - R^2 is rounded at 2^-p of |o - C|^2 = 5..65 R^2 (the origin 2 to 8 radii
    // back), while b^2 - |d|^2 c is 2^(k+1) R^2 |d|^2: the sign flips for 2^k below 2^-(p-5) to 2^-(p-1).
    p.mild = -(bits - 5), p.stiff = -(bits - 1);
    p.why = arith + ", b^2 - a c: c is rounded at 2^-p of |o - C|^2 (5 to 65 R^2) while the discriminant is 2^(k+1) R^2";
    return p;
  }
  return std::nullopt;
}

Agreement agreement(const gen::Knob& knob, const verify::StabilityCurve& c, const verify::Break& b, const Prediction& p) {
  const int dir = direction(knob);
  std::vector<int> swept;
  for (const auto& s : c.steps)
    if (s.stats.cases > 0) swept.push_back(s.exponent);
  if (!b.class_errors) {
    if (p.never || swept.empty()) return Agreement::as_predicted;
    // The window starts beyond the swept range: nothing was due.
    return p.mild * dir > swept.back() * dir ? Agreement::as_predicted : Agreement::later;
  }
  if (p.never) return Agreement::earlier;
  const auto it = std::find(swept.begin(), swept.end(), *b.class_errors);
  const long hi = long(*b.class_errors) * dir;
  const long lo = it == swept.begin() || it == swept.end() ? std::numeric_limits<long>::min() : long(*(it - 1)) * dir;
  const long wa = std::min(long(p.mild) * dir, long(p.stiff) * dir), wb = std::max(long(p.mild) * dir, long(p.stiff) * dir);
  if (hi < wa) return Agreement::earlier;
  if (lo >= wb) return Agreement::later;
  return Agreement::as_predicted;
}

std::string break_cell(const gen::Knob& knob, std::optional<int> exponent) {
  if (exponent) return pow2_text(*exponent);
  return knob.exponents.empty() ? "never in range" : "never up to " + pow2_text(knob.exponents.back());
}

std::string prediction_cell(const std::optional<Prediction>& p) {
  if (!p) return "";
  if (p->never) return "never in range";
  if (p->mild == p->stiff) return pow2_text(p->mild);
  return pow2_text(p->mild) + " .. " + pow2_text(p->stiff);
}

std::string breaks_table(const verify::StabilityRun& run) {
  std::string s =
      "| knob | method | class errors > 0.1% from | median t error > 1 ulp from | predicted class break | measured |\n"
      "|---|---|---|---|---|---|\n";
  for (const auto& c : run.curves) {
    const gen::Knob* k = gen::find_knob(c.knob);
    if (!k) continue;
    const verify::Break b = verify::find_break(c);
    const auto p = predict(*k, c.method, c.precision, c.promise);
    std::string verdict;
    if (p) {
      const Agreement a = agreement(*k, c, b, *p);
      verdict = verdict_text(a);
      if (const auto why = reason(*k, c, b, a); !why.empty()) verdict += ": " + why;
    }
    s += fmt::format("| {} | {} | {} | {} | {} | {} |\n", c.knob, c.method, break_cell(*k, b.class_errors),
                     break_cell(*k, b.t_error), prediction_cell(p), verdict);
  }
  return s;
}

std::vector<std::string> prediction_sentences(const verify::StabilityRun& run) {
  std::vector<std::string> out;
  for (const auto& knob_name : run.knobs) {
    const gen::Knob* k = gen::find_knob(knob_name);
    if (!k) continue;
    // Group the methods by prediction (same derivation and window), in order of first appearance.
    std::vector<std::pair<std::string, std::vector<std::string>>> groups;
    for (const auto& c : run.curves) {
      if (c.knob != knob_name) continue;
      const auto p = predict(*k, c.method, c.precision, c.promise);
      if (!p) continue;
      const verify::Break b = verify::find_break(c);
      const Agreement a = agreement(*k, c, b, *p);
      std::string item = fmt::format("{} {} ({}", c.method, break_cell(*k, b.class_errors), verdict_text(a));
      if (const auto why = reason(*k, c, b, a); !why.empty()) item += ": " + why;
      item += ")";
      const std::string head = fmt::format("{}, predicted {}", p->why, prediction_cell(p));
      auto g = std::find_if(groups.begin(), groups.end(), [&](const auto& x) { return x.first == head; });
      if (g == groups.end()) groups.push_back({head, {item}});
      else g->second.push_back(item);
    }
    // Knobs without a derivation: the exact-class promise alone says nothing about the knob.
    if (std::all_of(groups.begin(), groups.end(), [](const auto& g) { return g.first.rfind("promises the exact class", 0) == 0; }))
      continue;
    std::string s = fmt::format("**{}** ({}, first class errors above 0.1%): ", knob_name, k->quantity);
    for (std::size_t i = 0; i < groups.size(); ++i) {
      if (i) s += "; ";
      s += groups[i].first + "; measured ";
      for (std::size_t j = 0; j < groups[i].second.size(); ++j) s += (j ? ", " : "") + groups[i].second[j];
    }
    out.push_back(s + ".");
  }
  return out;
}

}  // namespace rayproof::report
