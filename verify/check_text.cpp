#include "verify/check_text.h"

#include <fmt/core.h>

#include <algorithm>

#include "verify/ulp_text.h"

namespace rayproof::verify {

std::string plural(std::size_t n, const char* one, const char* many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

namespace {
std::string percent(std::size_t n, std::size_t of) { return fmt::format("{:.3g}%", of ? 100.0 * double(n) / double(of) : 0.0); }

/// Every family checked is of triangle pairs: a hit is then "they meet", a miss "disjoint".
bool pairs_only(const CheckResult& r) {
  return !r.families.empty() &&
         std::all_of(r.families.begin(), r.families.end(), [](const FamilyCheck& f) { return f.kind == io::Kind::tritri; });
}
}  // namespace

std::string check_table(const CheckResult& r) {
  // Cells first, then each column as wide as its widest cell: a t error beyond 10^6 ulps carries its
  // reading, "4.5e+18 (leading bits wrong)".
  std::vector<std::vector<std::string>> rows;
  const bool pairs = pairs_only(r);
  rows.push_back({"family", "cases", pairs ? "false meets" : "false hit", pairs ? "false disjoint" : "false miss",
                  "wrong class", "t median", "t p99", "t max", fmt::format("> {} ulp", r.ulp_tolerance), "failures"});
  auto row = [&](const std::string& name, const Stats& s, std::size_t over_n, std::size_t fails) {
    // A pair's answer has no t: its t columns are "-".
    auto t_cell = [&](double q) { return pairs ? std::string("-") : ulp_text(s.ulp_quantile(q), r.precision); };
    rows.push_back({name, std::to_string(s.cases), std::to_string(s.false_hit), std::to_string(s.false_miss),
                    std::to_string(s.wrong_hit_class + s.wrong_class), t_cell(0.5), t_cell(0.99), t_cell(1.0),
                    pairs ? std::string("-") : std::to_string(over_n), std::to_string(fails)});
  };
  for (const auto& f : r.families) row(f.family, f.stats, f.over_tolerance, f.failures.size());
  row("(all)", r.total(), r.over_tolerance(), r.failures());
  std::vector<std::size_t> width{24, 7, 9, 10, 11, 8, 8, 8, 9, 8};
  for (const auto& cells : rows)
    for (std::size_t c = 0; c < cells.size(); ++c) width[c] = std::max(width[c], cells[c].size());
  std::string t;
  for (const auto& cells : rows) {
    for (std::size_t c = 0; c < cells.size(); ++c)
      t += c == 0 ? fmt::format("{:<{}}", cells[c], width[c]) : fmt::format(" {:>{}}", cells[c], width[c]);
    t += "\n";
  }
  return t;
}

std::vector<std::string> reproducer_lines(const CheckResult& r) {
  std::vector<std::string> out;
  for (const auto& f : r.families)
    for (const auto& w : f.worst) {
      const auto& j = w.judged;
      out.push_back(fmt::format("{}  # {}: {}, got {}, exact {}{}{}", io::format_case(j.input), w.family,
                                to_string(j.verdict),
                                // a pair's coarse answer as given (`hit`, `miss`), its full one as its class alone
                                j.input.kind == io::Kind::tritri ? io::format_answer(j.got) : io::format_result(j.got),
                                io::format_result(j.want),
                                j.verdict == Verdict::agree ? fmt::format(" ({} ulps)", ulp_text(j.ulps, r.precision)) : "",
                                w.minimized ? ", minimized" : ""));
    }
  for (const auto& f : r.families)
    for (const auto& kf : f.failures)
      out.push_back(fmt::format("{}  # {}: kernel failure: {}", io::format_case(kf.input), f.family, kf.what));
  return out;
}

std::vector<std::string> check_sentences(const CheckResult& r) {
  std::vector<std::string> s;
  const Stats t = r.total();
  const std::size_t errors = t.class_errors();
  const bool pairs = pairs_only(r);
  if (errors == 0)
    s.push_back(fmt::format("No class error in {}.", plural(t.cases, pairs ? "pair" : "case", pairs ? "pairs" : "cases")));
  else if (pairs)
    s.push_back(fmt::format("{} of {} pairs ({}) have a class error: {} (disjoint, called meeting), {} (meeting, "
                            "called disjoint), {}.", errors, t.cases, percent(errors, t.cases),
                            plural(t.false_hit, "false meets", "false meets"),
                            plural(t.false_miss, "false disjoint", "false disjoints"),
                            plural(t.wrong_hit_class + t.wrong_class, "wrong class", "wrong classes")));
  else
    s.push_back(fmt::format("{} of {} cases ({}) have a class error: {}, {}, {}.", errors, t.cases,
                            percent(errors, t.cases), plural(t.false_hit, "false hit", "false hits"),
                            plural(t.false_miss, "false miss", "false misses"),
                            plural(t.wrong_hit_class + t.wrong_class, "wrong class", "wrong classes")));
  if (pairs && t.unjudged > 0)
    s.push_back(fmt::format("{} answered meets-or-not whose exact class is degenerate or invalid are not judged.",
                            plural(t.unjudged, "pair", "pairs")));
  const std::size_t with_t = t.ulps.size();
  const std::size_t over = r.over_tolerance();
  if (pairs) {
    // a pair's answer carries no t: nothing to say about t
  } else if (with_t == 0)
    s.push_back("No class-correct case carries a t to compare.");
  else if (over == 0)
    s.push_back(fmt::format("Every t of the {} class-correct cases that carry one is within {} of exact (largest: {}).",
                            with_t, plural(r.ulp_tolerance, "ulp", "ulps"), ulp_text(t.ulp_quantile(1.0), r.precision)));
  else
    s.push_back(fmt::format("{} of the {} class-correct cases that carry a t ({}) are more than {} off (largest: {}).",
                            over, with_t, percent(over, with_t), plural(r.ulp_tolerance, "ulp", "ulps"),
                            ulp_text(t.ulp_quantile(1.0), r.precision)));
  if (const std::size_t f = r.failures(); f > 0)
    s.push_back(fmt::format("The kernel failed (crashed, hung or answered unreadably) on {}.", plural(f, "case", "cases")));
  std::size_t broken = 0;
  for (const auto& p : r.promises) {
    if (p.kept) {
      if (p.promise == "watertight")
        s.push_back("Promise watertight: kept (no false miss and no failure on tri_edge and tri_vertex).");
      else if (p.promise == "exact-class")
        s.push_back("Promise exact-class: kept (no class error and no failure on any family).");
      else if (p.promise == "no-false-negative")
        s.push_back(pairs ? "Promise no-false-negative: kept (no pair that meets called disjoint, and no failure)."
                          : "Promise no-false-negative: kept (no false miss and no failure on any family).");
      else
        s.push_back(fmt::format("Promise {}: kept (no class-correct t further off).", p.promise));
      continue;
    }
    ++broken;
    if (p.promise == "watertight")
      s.push_back(fmt::format("Promise watertight: BROKEN by {} (false misses and failures on tri_edge and tri_vertex).",
                              plural(p.violations, "case", "cases")));
    else if (p.promise == "exact-class")
      s.push_back(fmt::format("Promise exact-class: BROKEN by {} (class errors and failures).",
                              plural(p.violations, "case", "cases")));
    else if (p.promise == "no-false-negative")
      s.push_back(fmt::format("Promise no-false-negative: BROKEN by {} ({} and failures).",
                              plural(p.violations, pairs ? "pair" : "case", pairs ? "pairs" : "cases"),
                              pairs ? "false disjoints" : "false misses"));
    else
      s.push_back(fmt::format("Promise {}: BROKEN by {} with a t further off.", p.promise,
                              plural(p.violations, "case", "cases")));
  }
  if (!r.promises.empty())
    s.push_back(broken == 0 ? (r.promises.size() == 1 ? std::string("The stated promise is kept.")
                                                      : fmt::format("All {} stated promises are kept.", r.promises.size()))
                            : fmt::format("{} of {} stated {} broken.", broken, r.promises.size(),
                                          r.promises.size() == 1 ? "promise is" : "promises are"));
  return s;
}

}  // namespace rayproof::verify
