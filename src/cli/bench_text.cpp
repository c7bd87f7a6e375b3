#include "cli/bench_text.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <tuple>

namespace rayproof::cli {

namespace {
std::string fixed(double v, int decimals) { return fmt::format("{:.{}f}", v, decimals); }

/// A JSON string (the names here are file names and method names: quotes and backslashes escaped,
/// control characters as \u00XX).
std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\', out += c;
    else if (static_cast<unsigned char>(c) < 0x20) out += fmt::format("\\u{:04x}", int(c));
    else out += c;
  }
  return out + "\"";
}

using Key = std::tuple<std::string, std::string, std::string, std::string, std::string>;  // mesh, method, rays, query, path
std::map<Key, const BenchRow*> index_rows(const std::vector<BenchRow>& rows) {
  std::map<Key, const BenchRow*> m;
  for (const auto& r : rows) m[{r.mesh, r.method, r.rays, r.query, r.path}] = &r;
  return m;
}
}  // namespace

BenchTarget check_target(const std::string& mesh, const std::string& what, const std::string& rays,
                         const std::string& query, double value, double goal, Goal kind, int decimals) {
  BenchTarget t{mesh, what, rays, query, fixed(value, decimals), fixed(goal, decimals), false, ""};
  // Decided on the printed numbers, so that the words agree with what stands beside them.
  const double shown = std::strtod(t.value.c_str(), nullptr), g = std::strtod(t.goal.c_str(), nullptr);
  t.met = kind == Goal::at_least ? shown >= g : shown <= g;
  if (t.met) {
    t.verdict = "met";
  } else {
    const double miss = kind == Goal::at_least ? g - shown : shown - g;
    t.verdict = "missed by " + fixed(miss, decimals);
    if (g > 0) {
      const double pct = 100.0 * miss / g;
      t.verdict += pct >= 10 ? fmt::format(" ({:.0f}% of the goal)", pct) : fmt::format(" ({:.2g}% of the goal)", pct);
    }
  }
  return t;
}

BenchTarget scaling_target(const std::string& mesh, const std::string& what, const std::string& rays,
                           const std::string& query, double speedup) {
  BenchTarget t = check_target(mesh, what, rays, query, speedup, 1.9, Goal::at_least, 2);
  // A speed-up above 2.10 on two threads is more than twice one thread's rate. It showed up on a
  // shared machine (a disturbed one-thread timing) and also on a quiet one, for every method and for
  // Embree alike (2.0-2.5 on this project's 2-vCPU VM, cause not measured), so the pair of
  // timings does not measure what the target asks and is not judged either way.
  if (std::strtod(t.value.c_str(), nullptr) > 2.1) {
    t.met = false;
    t.verdict = "not judged: above 2.10, more than twice one thread's rate";
  }
  return t;
}

std::vector<BenchTarget> bench_targets(const std::vector<BenchRow>& rows, const std::vector<BenchBuild>& builds) {
  std::vector<BenchTarget> out;
  const auto idx = index_rows(rows);
  auto find = [&](const BenchRow& r, const char* method) {
    const auto it = idx.find({r.mesh, method, r.rays, r.query, r.path});
    return it == idx.end() ? nullptr : it->second;
  };
  struct Ratio {
    const char *method, *against;
    double goal;
  };
  const Ratio ratios[] = {{"robust", "embree-robust", 1.0}, {"certified", "embree-robust", 0.8}, {"float", "embree", 1.0}};
  for (const Ratio& q : ratios)
    for (const auto& r : rows) {
      if (r.method != q.method) continue;
      const BenchRow* e = find(r, q.against);  // on the same path
      if (!e || !(e->mrays > 0)) continue;
      const std::string what = r.path == "single" ? fmt::format("{} / {} (1 thread)", q.method, q.against)
                                                  : fmt::format("{} / {} ({}, 1 thread)", q.method, q.against, r.path);
      out.push_back(check_target(r.mesh, what, r.rays, r.query, r.mrays / e->mrays, q.goal, Goal::at_least, 2));
    }
  for (const char* m : {"robust", "certified", "float"})
    for (const auto& r : rows)
      if (r.method == m && r.path == "single" && r.scaled_threads == 2 && r.mrays > 0)
        out.push_back(scaling_target(r.mesh, fmt::format("{} 2 threads / 1 thread", m), r.rays, r.query,
                                     r.mrays_scaled / r.mrays));
  for (const auto& b : builds)
    if (b.embree_s > 0)
      out.push_back(check_target(b.mesh, fmt::format("build / Embree's build ({} thread{})", b.threads, b.threads == 1 ? "" : "s"),
                                 "", "", b.ours_s / b.embree_s, 1.0, Goal::at_most, 2));
  std::map<std::string, bool> bytes_done, leaks_done;
  for (const auto& r : rows) {
    if (r.method == "robust" && r.bytes >= 0 && !bytes_done[r.mesh]) {
      bytes_done[r.mesh] = true;
      // What robust's queries read (nodes and leaf groups); the table's `held` column has the rest.
      out.push_back(check_target(r.mesh, "robust bytes per triangle", "", "", r.bytes, 64.0, Goal::at_most, 1));
    }
    if ((r.method == "robust" || r.method == "certified") && r.leaks >= 0 && !leaks_done[r.mesh + "/" + r.method]) {
      leaks_done[r.mesh + "/" + r.method] = true;
      out.push_back(check_target(r.mesh, r.method + " leaks", "", "", double(r.leaks), 0.0, Goal::at_most, 0));
    }
  }
  return out;
}

std::string isa_lines(const BenchIsa& isa) {
  if (isa.nodes.empty()) return "";
  std::string have, lack;
  for (const auto& [feature, present] : isa.cpu) {
    std::string& list = present ? have : lack;
    list += (list.empty() ? "" : " ") + feature;
  }
  std::string cpu = have;
  if (!lack.empty()) cpu += (cpu.empty() ? "no " : ", no ") + lack;
  std::string out = fmt::format("isa: rayproof nodes {}, leaves {} (cpu: {})\n", isa.nodes, isa.leaves, cpu);
  std::string sides;
  std::vector<std::pair<std::string, std::string>> hows;  // how it is known, then the kernels it named
  for (const auto& c : isa.competitors) {
    if (c.isa.empty()) continue;
    sides += fmt::format("{}{} {}", sides.empty() ? "" : ", ", c.name, c.isa);
    auto it = std::find_if(hows.begin(), hows.end(), [&](const auto& h) { return h.first == c.how; });
    if (it == hows.end()) it = hows.insert(hows.end(), {c.how, ""});
    if (!c.kernel.empty()) it->second += fmt::format("{}{} {}", it->second.empty() ? "" : ", ", c.name, c.kernel);
  }
  if (sides.empty()) return out;
  for (const auto& [how, kernels] : hows)
    if (!how.empty() || !kernels.empty())
      sides += " (" + how + (how.empty() || kernels.empty() ? "" : ": ") + kernels + ")";
  return out + "isa: " + sides + "\n";
}

std::string avx2_ratio_lines(const std::vector<BenchRow>& rows) {
  const auto idx = index_rows(rows);
  const std::string suffix = "-avx2";
  // One line per mesh, rays, query and avx2 competitor, in the rows' order; paths within it.
  std::vector<std::tuple<std::string, std::string, std::string, std::string>> order;  // mesh, rays, query, method
  std::map<std::tuple<std::string, std::string, std::string, std::string>, std::string> parts;
  for (const auto& r : rows) {
    if (r.method.size() <= suffix.size() || r.method.compare(r.method.size() - suffix.size(), suffix.size(), suffix) != 0 ||
        r.method.rfind("embree", 0) != 0)
      continue;
    const std::string base = r.method.substr(0, r.method.size() - suffix.size());
    const auto b = idx.find({r.mesh, base, r.rays, r.query, r.path});
    if (b == idx.end()) continue;
    // The rates as the table prints them, and the ratio of those printed numbers.
    const std::string a_txt = fixed(r.mrays, 3), b_txt = fixed(b->second->mrays, 3);
    const double a = std::strtod(a_txt.c_str(), nullptr), d = std::strtod(b_txt.c_str(), nullptr);
    const std::string ratio = d > 0 ? fixed(a / d, 2) : "-";
    const std::tuple<std::string, std::string, std::string, std::string> key{r.mesh, r.rays, r.query, r.method};
    auto [it, fresh] = parts.try_emplace(key, fmt::format("{} {} {}: {} / {} ", r.mesh, r.rays, r.query, r.method, base));
    if (fresh) order.push_back(key);
    else it->second += ", ";
    it->second += fmt::format("{} / {} = {} ({})", a_txt, b_txt, ratio, r.path);
  }
  std::string out;
  for (const auto& k : order) out += parts[k] + "\n";
  return out;
}

std::string bench_table(const std::vector<BenchRow>& rows) {
  const auto idx = index_rows(rows);
  // B/tri read: what the method's queries read (nodes, leaf groups or records, vertices); held: all
  // its structures hold (MeshCaster and scene::Accel keep the leaf records for every method).
  // The method column is as wide as its longest name (at least 18: `--embree-tree` adds "@ tree").
  std::size_t mw = 18;
  for (const auto& r : rows) mw = std::max(mw, r.method.size());
  std::string t = fmt::format("{:<20} {:<{}} {:<8} {:<8} {:<8} {:>8} {:>10} {:>10} {:>9} {:>10} {:>10} {:>7} {:>14}\n", "mesh",
                              "method", mw, "rays", "query", "path", "count", "Mrays/s 1t", "speed-up", "build s", "x embree-r",
                              "B/tri read", "held", "leaks");
  for (const auto& r : rows) {
    const auto er = idx.find({r.mesh, "embree-robust", r.rays, r.query, r.path});
    const bool has_er = er != idx.end() && er->second->mrays > 0;
    t += fmt::format("{:<20} {:<{}} {:<8} {:<8} {:<8} {:>8} {:>10.3f} {:>10} {:>9.3f} {:>10} {:>10} {:>7} {:>14}\n", r.mesh,
                     r.method, mw, r.rays, r.query, r.path, r.n, r.mrays,
                     r.scaled_threads > 0 && r.mrays > 0 ? fmt::format("{:.2f}x/{}t", r.mrays_scaled / r.mrays, r.scaled_threads) : "-",
                     r.build_s, has_er ? fixed(r.mrays / er->second->mrays, 3) : "-", r.bytes < 0 ? "-" : fixed(r.bytes, 1),
                     r.bytes_held < 0 ? "-" : fixed(r.bytes_held, 1), r.leaks < 0 ? "-" : fmt::format("{}/{}", r.leaks, r.leak_rays));
  }
  return t;
}

std::string build_table(const std::vector<BenchBuild>& builds) {
  std::string t = fmt::format("{:<20} {:>7} {:>10} {:>10} {:>8}\n", "mesh", "threads", "build s", "Embree s", "ratio");
  for (const auto& b : builds)
    t += fmt::format("{:<20} {:>7} {:>10.4f} {:>10} {:>8}\n", b.mesh, b.threads, b.ours_s,
                     b.embree_s > 0 ? fixed(b.embree_s, 4) : "-", b.embree_s > 0 ? fixed(b.ours_s / b.embree_s, 2) : "-");
  return t;
}

std::string targets_table(const std::vector<BenchTarget>& targets) {
  std::string t = fmt::format("{:<20} {:<48} {:<8} {:<8} {:>8} {:>8}  {}\n", "mesh", "target", "rays", "query", "value",
                              "goal", "verdict");
  for (const auto& x : targets)
    t += fmt::format("{:<20} {:<48} {:<8} {:<8} {:>8} {:>8}  {}\n", x.mesh, x.what, x.rays.empty() ? "-" : x.rays,
                     x.query.empty() ? "-" : x.query, x.value, x.goal, x.verdict);
  return t;
}

std::string bench_json(const std::vector<BenchRow>& rows, const std::vector<BenchTarget>& targets, const BenchIsa* isa) {
  const auto idx = index_rows(rows);
  std::vector<std::string> items;
  for (const auto& r : rows) {
    const auto er = idx.find({r.mesh, "embree-robust", r.rays, r.query, r.path});
    const bool has_er = er != idx.end() && er->second->mrays > 0;
    items.push_back(fmt::format(
        "{{\"method\": {}, \"rays\": {}, \"query\": {}, \"path\": {}, \"mesh\": {}, \"ray_count\": {}, \"threads\": 1, "
        "\"mrays_per_s\": {}, \"build_s\": {}, \"bytes_per_tri\": {}, \"bytes_held_per_tri\": {}, \"ratio_to_embree_robust\": {}, \"leaks\": {}, "
        "\"leak_rays\": {}, \"scaling_threads\": {}, \"mrays_per_s_scaled\": {}, \"scaling\": {}}}",
        json_string(r.method), json_string(r.rays), json_string(r.query), json_string(r.path), json_string(r.mesh), r.n,
        r.mrays, r.build_s, r.bytes < 0 ? "null" : fixed(r.bytes, 1),
        r.bytes_held < 0 ? "null" : fixed(r.bytes_held, 1), has_er ? fixed(r.mrays / er->second->mrays, 3) : "null",
        r.leaks < 0 ? "null" : std::to_string(r.leaks), r.leak_rays, r.scaled_threads > 0 ? std::to_string(r.scaled_threads) : "null",
        r.scaled_threads > 0 ? fmt::format("{}", r.mrays_scaled) : "null",
        r.scaled_threads > 0 && r.mrays > 0 ? fixed(r.mrays_scaled / r.mrays, 3) : "null"));
  }
  for (const auto& t : targets)
    items.push_back(fmt::format("{{\"target\": {}, \"mesh\": {}, \"rays\": {}, \"query\": {}, \"value\": {}, \"goal\": {}, "
                                "\"met\": {}, \"verdict\": {}}}",
                                json_string(t.what), json_string(t.mesh), t.rays.empty() ? "null" : json_string(t.rays),
                                t.query.empty() ? "null" : json_string(t.query), t.value, t.goal, t.met ? "true" : "false",
                                json_string(t.verdict)));
  if (isa && !isa->nodes.empty()) {
    std::string cpu, sides;
    for (const auto& [feature, present] : isa->cpu)
      cpu += fmt::format("{}{}: {}", cpu.empty() ? "" : ", ", json_string(feature), present ? "true" : "false");
    for (const auto& c : isa->competitors)
      if (!c.isa.empty())
        sides += fmt::format("{}{{\"name\": {}, \"isa\": {}, \"kernel\": {}, \"how\": {}}}", sides.empty() ? "" : ", ",
                             json_string(c.name), json_string(c.isa), json_string(c.kernel), json_string(c.how));
    items.push_back(fmt::format("{{\"isa\": {{\"rayproof\": {{\"nodes\": {}, \"leaves\": {}, \"cpu\": {{{}}}}}, "
                                "\"competitors\": [{}]}}}}",
                                json_string(isa->nodes), json_string(isa->leaves), cpu, sides));
  }
  std::string out = "[\n";
  for (std::size_t i = 0; i < items.size(); ++i) out += "  " + items[i] + (i + 1 < items.size() ? ",\n" : "\n");
  return out + "]\n";
}

std::string first_batch_line(double first_s, std::size_t points, double best_mpts) {
  if (!(best_mpts > 0)) return {};
  // The rate as printed, so that the reader can redo the division.
  const std::string rate = fmt::format("{:.4f}", best_mpts);
  const double best_s = double(points) / (std::stod(rate) * 1e6);
  const std::string first = fmt::format("{:.3f}", first_s), best = fmt::format("{:.3f}", best_s);
  const double more = std::stod(first) - std::stod(best);
  const std::string how = more > 0 ? fmt::format("{:.3f} s more than", more) : std::string("no more than");
  return fmt::format("the first batch took {} s, {} the best batch after it ({} s at {} Mpoints/s)", first, how, best, rate);
}

}  // namespace rayproof::cli
