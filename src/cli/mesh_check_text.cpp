#include "cli/mesh_check_text.h"

#include <fmt/core.h>

#include "verify/check_text.h"

namespace rayproof::cli {

using verify::plural;

namespace {
std::string percent(std::size_t n, std::size_t of) { return fmt::format("{:.3g}%", of ? 100.0 * double(n) / double(of) : 0.0); }
}  // namespace

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
