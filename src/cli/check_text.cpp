#include "cli/check_text.h"

#include <fmt/core.h>

#include <limits>

namespace rayproof::cli {

namespace {
std::string plural(std::size_t n, const char* one, const char* many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}
std::string percent(std::size_t n, std::size_t of) { return fmt::format("{:.3g}%", of ? 100.0 * double(n) / double(of) : 0.0); }
}  // namespace

std::string ulp_text(std::uint64_t u) {
  return u == std::numeric_limits<std::uint64_t>::max() ? std::string("NaN t") : std::to_string(u);
}

std::string check_table(const verify::CheckResult& r) {
  const std::string over = fmt::format("> {} ulp", r.ulp_tolerance);
  auto row = [&](const std::string& name, const verify::Stats& s, std::size_t over_n, std::size_t fails) {
    return fmt::format("{:<24} {:>7} {:>9} {:>10} {:>11} {:>8} {:>8} {:>8} {:>9} {:>8}\n", name, s.cases, s.false_hit,
                       s.false_miss, s.wrong_hit_class + s.wrong_class, ulp_text(s.ulp_quantile(0.5)),
                       ulp_text(s.ulp_quantile(0.99)), ulp_text(s.ulp_quantile(1.0)), over_n, fails);
  };
  std::string t = fmt::format("{:<24} {:>7} {:>9} {:>10} {:>11} {:>8} {:>8} {:>8} {:>9} {:>8}\n", "family", "cases",
                              "false hit", "false miss", "wrong class", "t median", "t p99", "t max", over, "failures");
  for (const auto& f : r.families) t += row(f.family, f.stats, f.over_tolerance, f.failures.size());
  t += row("(all)", r.total(), r.over_tolerance(), r.failures());
  return t;
}

std::vector<std::string> reproducer_lines(const verify::CheckResult& r) {
  std::vector<std::string> out;
  for (const auto& f : r.families)
    for (const auto& w : f.worst) {
      const auto& j = w.judged;
      out.push_back(fmt::format("{}  # {}: {}, got {}, exact {}{}{}", io::format_case(j.input), w.family,
                                verify::to_string(j.verdict), io::format_result(j.got), io::format_result(j.want),
                                j.verdict == verify::Verdict::agree ? fmt::format(" ({} ulps)", ulp_text(j.ulps)) : "",
                                w.minimized ? ", minimized" : ""));
    }
  for (const auto& f : r.families)
    for (const auto& kf : f.failures)
      out.push_back(fmt::format("{}  # {}: kernel failure: {}", io::format_case(kf.input), f.family, kf.what));
  return out;
}

std::vector<std::string> check_sentences(const verify::CheckResult& r) {
  std::vector<std::string> s;
  const verify::Stats t = r.total();
  const std::size_t errors = t.class_errors();
  if (errors == 0)
    s.push_back(fmt::format("No class error in {}.", plural(t.cases, "case", "cases")));
  else
    s.push_back(fmt::format("{} of {} cases ({}) have a class error: {}, {}, {}.", errors, t.cases,
                            percent(errors, t.cases), plural(t.false_hit, "false hit", "false hits"),
                            plural(t.false_miss, "false miss", "false misses"),
                            plural(t.wrong_hit_class + t.wrong_class, "wrong class", "wrong classes")));
  const std::size_t with_t = t.ulps.size();
  const std::size_t over = r.over_tolerance();
  if (with_t == 0)
    s.push_back("No class-correct case carries a t to compare.");
  else if (over == 0)
    s.push_back(fmt::format("Every t of the {} class-correct cases that carry one is within {} of exact (largest: {}).",
                            with_t, plural(r.ulp_tolerance, "ulp", "ulps"), ulp_text(t.ulp_quantile(1.0))));
  else
    s.push_back(fmt::format("{} of the {} class-correct cases that carry a t ({}) are more than {} off (largest: {}).",
                            over, with_t, percent(over, with_t), plural(r.ulp_tolerance, "ulp", "ulps"),
                            ulp_text(t.ulp_quantile(1.0))));
  if (const std::size_t f = r.failures(); f > 0)
    s.push_back(fmt::format("The kernel failed (crashed, hung or answered unreadably) on {}.", plural(f, "case", "cases")));
  std::size_t broken = 0;
  for (const auto& p : r.promises) {
    if (p.kept) {
      if (p.promise == "watertight")
        s.push_back("Promise watertight: kept (no false miss and no failure on tri_edge and tri_vertex).");
      else if (p.promise == "exact-class")
        s.push_back("Promise exact-class: kept (no class error and no failure on any family).");
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

}  // namespace rayproof::cli

namespace rayproof::cli {

namespace {
struct MeshTotals {
  std::size_t triangles = 0;
  std::uint64_t rays = 0, candidates = 0, leaks = 0, without = 0, failures = 0, leaky_meshes = 0;
};
MeshTotals totals(const std::vector<verify::MeshCheck>& r) {
  MeshTotals t;
  for (const auto& m : r) {
    t.triangles += m.triangles, t.rays += m.rays, t.candidates += m.candidate_cases, t.leaks += m.leaks;
    t.without += m.rays_without_candidates, t.failures += m.failures.size(), t.leaky_meshes += m.leaks > 0;
  }
  return t;
}
}  // namespace

std::string mesh_table(const std::vector<verify::MeshCheck>& r) {
  auto row = [](const std::string& name, std::size_t tris, std::uint64_t rays, std::uint64_t cand, std::uint64_t leaks,
                std::uint64_t without, std::uint64_t fails) {
    return fmt::format("{:<32} {:>9} {:>9} {:>10} {:>7} {:>12} {:>8}\n", name, tris, rays, cand, leaks, without, fails);
  };
  std::string s = fmt::format("{:<32} {:>9} {:>9} {:>10} {:>7} {:>12} {:>8}\n", "mesh", "triangles", "rays",
                              "candidates", "leaks", "no candidate", "failures");
  for (const auto& m : r)
    s += row(m.mesh, m.triangles, m.rays, m.candidate_cases, m.leaks, m.rays_without_candidates, m.failures.size());
  const MeshTotals t = totals(r);
  s += row("(all)", t.triangles, t.rays, t.candidates, t.leaks, t.without, t.failures);
  return s;
}

std::vector<std::string> leak_lines(const std::vector<verify::MeshCheck>& r, const std::string& finder) {
  std::vector<std::string> out;
  for (const auto& m : r) {
    std::size_t k = 0;
    for (const auto& leak : m.reproducers) {
      out.push_back(fmt::format("# leak {} of {} on {}: ray from {} {} {} along {} {} {} slipped between {}", ++k,
                                m.leaks, m.mesh, io::format_double(leak.ray.o.x), io::format_double(leak.ray.o.y),
                                io::format_double(leak.ray.o.z), io::format_double(leak.ray.d.x),
                                io::format_double(leak.ray.d.y), io::format_double(leak.ray.d.z),
                                plural(leak.candidates.size(), "triangle", "triangles")) +
                    (leak.candidate_count > leak.candidates.size()
                         ? fmt::format(" (and missed {} more candidates near it)",
                                       leak.candidate_count - leak.candidates.size())
                         : std::string()));
      for (const auto& c : leak.candidates)
        out.push_back(fmt::format("{}  # kernel: {}; {}: {} {}", io::format_case(c.input), io::format_result(c.answer),
                                  finder, to_string(c.finder_contact), io::format_double(c.finder_t)));
    }
    for (const auto& f : m.failures)
      out.push_back(fmt::format("{}  # {}: kernel failure: {}", io::format_case(f.input), m.mesh, f.what));
  }
  return out;
}

std::vector<std::string> mesh_sentences(const std::vector<verify::MeshCheck>& r) {
  std::vector<std::string> s;
  const MeshTotals t = totals(r);
  if (t.leaks == 0)
    s.push_back(fmt::format("No leak: on each of the {} with candidates, the kernel hit a candidate triangle ({}).",
                            plural(t.rays - t.without, "ray", "rays"), plural(r.size(), "mesh", "meshes")));
  else
    s.push_back(fmt::format("{} of {} rays with candidates ({}) leaked: the kernel hit none of their candidate triangles; {} of {} leaked.",
                            t.leaks, t.rays - t.without, percent(t.leaks, t.rays - t.without), t.leaky_meshes,
                            plural(r.size(), "mesh", "meshes")));
  if (t.without > 0)
    s.push_back(fmt::format("{} found no candidate triangle (not charged to the kernel).", plural(t.without, "ray", "rays")));
  if (t.failures > 0)
    s.push_back(fmt::format("The kernel failed (crashed, hung or answered unreadably) on {}.",
                            plural(t.failures, "candidate case", "candidate cases")));
  s.push_back(t.leaks == 0 && t.failures == 0
                  ? std::string("Promise watertight: kept on every mesh.")
                  : fmt::format("Promise watertight: BROKEN by {} and {}.", plural(t.leaks, "leak", "leaks"),
                                plural(t.failures, "failure", "failures")));
  return s;
}

}  // namespace rayproof::cli
