#include "report/report_text.h"

#include "verify/ulp_text.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace rayproof::report {

namespace {

constexpr std::uint64_t kNaN = std::numeric_limits<std::uint64_t>::max();

std::string precision_name(Precision p) { return p == Precision::float32 ? "float" : "double"; }

/// The distinct values of `items` in first-seen order.
std::vector<std::string> distinct(const std::vector<std::string>& items) {
  std::vector<std::string> out;
  for (const auto& s : items)
    if (std::find(out.begin(), out.end(), s) == out.end()) out.push_back(s);
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// What the worst NaN case shows about its cause, from its numbers: a coordinate whose cube
/// overflows the precision, or an exact t of 0 (the ray starts on the surface).
std::string nan_context(const verify::Stats::Worst& w, Precision p) {
  double big = 0;
  for (int i = 0; i < io::field_count(w.input.kind); ++i) big = std::max(big, std::fabs(w.input.v[static_cast<std::size_t>(i)]));
  const double limit = p == Precision::float32 ? double(std::numeric_limits<float>::max()) : std::numeric_limits<double>::max();
  if (std::isfinite(big) && std::cbrt(limit) < big)
    return fmt::format(" (in the example a coordinate reaches {:.2g}: a product of three such overflows {})", big,
                       precision_name(p));
  if (w.want.t && *w.want.t == 0) return " (in the example the exact t is 0: the ray starts on the surface)";
  return "";
}

std::string t_text(const std::optional<double>& t) { return t ? fmt::format("{}", *t) : std::string("none"); }

}  // namespace

using verify::ulp_note;
using verify::ulp_number;

std::string ulp_text(std::uint64_t u, Precision p) { return verify::ulp_text(u, p); }

std::uint64_t tolerance(const Promise& promised, std::uint64_t report_tolerance) {
  return promised.t_ulps ? *promised.t_ulps : report_tolerance;
}

bool error_free(const verify::Stats& s, std::uint64_t tol) {
  return s.cases > 0 && s.class_errors() == 0 && s.kernel_failures == 0 && s.ulp_quantile(1.0) <= tol;
}

std::string error_free_definition(std::uint64_t report_tolerance) {
  return fmt::format(
      "*Error-free* below means: no class error, and every class-correct t within the tolerance the method "
      "promises on the kind (1 ulp for `exact` and `certified`), else within {} ulp{} of its own precision "
      "(`report --ulp-tolerance`). In t error columns, *rel. <= x* bounds the relative error of t; *leading "
      "bits wrong* means t is off by about a factor of 2 or more, or lies on the other side of zero; *NaN t* "
      "means the class was right but t was NaN (explained under \"t errors that need a word\").",
      report_tolerance, report_tolerance == 1 ? "" : "s");
}

std::vector<std::string> kind_sentences(io::Kind kind, const std::vector<Row>& rows, std::uint64_t report_tolerance) {
  std::vector<const Row*> mine;
  for (const auto& r : rows)
    if (r.kind == kind) mine.push_back(&r);
  std::vector<std::string> out;
  if (mine.empty()) return out;
  std::vector<std::string> method_list, group_list;
  for (const Row* r : mine) method_list.push_back(r->method), group_list.push_back(r->group);
  const auto methods = distinct(method_list), groups = distinct(group_list);
  const std::string k(io::to_string(kind));

  // Over every family of the kind: error-free on each, cheapest by time weighted by cases.
  std::string best;
  double best_ns = 0;
  for (const auto& m : methods) {
    bool ok = true;
    std::size_t families = 0, n = 0;
    double ns = 0;
    for (const Row* r : mine) {
      if (r->method != m) continue;
      ++families;
      ok = ok && error_free(r->stats, tolerance(r->promise, report_tolerance));
      ns += r->ns_per_case * double(r->stats.cases);
      n += r->stats.cases;
    }
    if (!ok || families != groups.size() || n == 0) continue;
    if (best.empty() || ns / double(n) < best_ns) best = m, best_ns = ns / double(n);
  }
  if (best.empty())
    out.push_back(fmt::format("No method was error-free on every {} family ({}).", k, groups.size()));
  else
    out.push_back(fmt::format("The cheapest method error-free on every {} family ({}) is `{}` at {:.1f} ns per case.", k,
                              groups.size(), best, best_ns));

  // Family by family.
  std::vector<std::pair<std::string, std::vector<std::string>>> by_method;  // in order of first family
  std::vector<std::string> none, t_beyond;
  for (const auto& g : groups) {
    const Row *free = nullptr, *class_ok = nullptr;
    for (const Row* r : mine) {
      if (r->group != g) continue;
      if (error_free(r->stats, tolerance(r->promise, report_tolerance)) && (!free || r->ns_per_case < free->ns_per_case))
        free = r;
      if (r->stats.class_errors() == 0 && r->stats.kernel_failures == 0 && r->stats.cases > 0 &&
          (!class_ok || r->ns_per_case < class_ok->ns_per_case))
        class_ok = r;
    }
    if (!free) {
      none.push_back(g);
    } else {
      auto it = std::find_if(by_method.begin(), by_method.end(), [&](const auto& e) { return e.first == free->method; });
      if (it == by_method.end()) by_method.push_back({free->method, {g}});
      else it->second.push_back(g);
    }
    if (class_ok && class_ok != free && !error_free(class_ok->stats, tolerance(class_ok->promise, report_tolerance))) {
      const std::uint64_t u = class_ok->stats.ulp_quantile(1.0);
      const std::string note = ulp_note(u, class_ok->precision);
      t_beyond.push_back(u == kNaN ? fmt::format("`{}` on {} (NaN t)", class_ok->method, g)
                                   : fmt::format("`{}` on {} (t off by up to {} {} ulps{})", class_ok->method, g,
                                                 ulp_number(u), precision_name(class_ok->precision),
                                                 note.empty() ? "" : ", " + note));
    }
  }
  std::string s = "Family by family, the cheapest error-free method is ";
  if (by_method.empty()) s = "Family by family, no method is error-free on any family";
  bool first = true;
  for (const auto& [m, gs] : by_method) {
    s += fmt::format("{}`{}` on {}", first ? "" : "; ", m, join(gs));
    first = false;
  }
  if (!none.empty() && !by_method.empty()) s += "; no method is error-free on " + join(none);
  out.push_back(s + ".");
  if (!t_beyond.empty())
    out.push_back("Where the cheapest method without a class error has t beyond tolerance: " + join(t_beyond) + ".");
  return out;
}

std::vector<std::string> promise_sentences(const std::vector<Row>& rows) {
  // Per method and promise (its description), the kinds in row order, and the tally over them.
  struct Entry {
    std::string method, promise;
    std::vector<std::string> kinds;
    std::size_t promised = 0, broken = 0;
  };
  std::vector<Entry> entries;
  for (const auto& r : rows) {
    if (!r.promise.any()) continue;
    const std::string d = r.promise.describe();
    auto it = std::find_if(entries.begin(), entries.end(), [&](const Entry& e) { return e.method == r.method && e.promise == d; });
    if (it == entries.end()) it = entries.insert(entries.end(), Entry{r.method, d, {}, 0, 0});
    const std::string k(io::to_string(r.kind));
    if (std::find(it->kinds.begin(), it->kinds.end(), k) == it->kinds.end()) it->kinds.push_back(k);
    it->promised += r.stats.promised;
    it->broken += r.stats.promise_broken;
  }
  std::vector<std::string> out;
  for (const auto& e : entries) {
    if (e.broken == 0)
      out.push_back(fmt::format("`{}` promises {} on {}: kept on all {} cases.", e.method, e.promise, join(e.kinds), e.promised));
    else
      out.push_back(fmt::format("`{}` promises {} on {}: broken on {} of {} cases.", e.method, e.promise, join(e.kinds),
                                e.broken, e.promised));
  }
  return out;
}

std::vector<std::string> t_error_sentences(const std::vector<Row>& rows) {
  std::vector<std::string> out;
  for (const auto& r : rows) {
    const auto& st = r.stats;
    const auto nan = static_cast<std::size_t>(std::count(st.ulps.begin(), st.ulps.end(), kNaN));
    if (nan > 0 && st.worst) {
      const auto& w = *st.worst;
      const bool is_nan = (w.got.t && std::isnan(*w.got.t)) || (w.got.t2 && std::isnan(*w.got.t2));
      out.push_back(fmt::format("`{}` on {}: the class was right but t was {} on {} of {} cases{}. For example (input "
                                "as the method saw it, its answer, the exact one): `{}  # got {}, exact {}`",
                                r.method, r.group, is_nan ? "NaN" : "NaN or missing", nan, st.cases, nan_context(w, r.precision),
                                io::format_case(w.input), io::format_answer(w.got), io::format_result(w.want)));
    }
  }
  for (const auto& r : rows) {
    const auto& st = r.stats;
    if (!st.worst || st.worst->ulps == kNaN || st.worst->ulps < 1000000000ULL) continue;
    const auto& w = *st.worst;
    // The t (or t2) that is off the most.
    std::optional<double> got = w.got.t, want = w.want.t;
    if (w.got.t2 && w.want.t2 && w.got.t && w.want.t &&
        std::fabs(*w.got.t2 - *w.want.t2) > std::fabs(*w.got.t - *w.want.t))
      got = w.got.t2, want = w.want.t2;
    std::string what;
    if (got && want && *want != 0 && std::isfinite(*got)) {
      const double rel = std::fabs(*got - *want) / std::fabs(*want);
      what = (std::signbit(*got) != std::signbit(*want) && *got != 0)
                 ? "t on the other side of zero"
                 : (rel >= 0.5 ? fmt::format("a relative error of {:.2g}: wrong in the leading bits", rel)
                               : fmt::format("a relative error of {:.2g}", rel));
    } else if (got && want && *want == 0 && std::isfinite(*got)) {
      what = "wrong in the leading bits: the exact t is 0 (the ray starts on the surface)";
    } else {
      what = "its t is not finite";
    }
    out.push_back(fmt::format("`{}` on {}: the largest t error is {} {} ulps, {} (got t = {}, exact t = {}): `{}`",
                              r.method, r.group, fmt::format("{:.2g}", double(w.ulps)), precision_name(r.precision), what,
                              t_text(got), t_text(want), io::format_case(w.input)));
  }
  return out;
}

std::string promise_cell(const verify::Stats& s) { return verify::promise_status(s); }

}  // namespace rayproof::report
