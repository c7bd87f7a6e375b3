// `rayproof bench`'s targets and output. Verdicts from known numbers (decided on
// the printed value), the targets a set of rows yields, and the JSON of a real run on a tiny closed
// mesh: fields, rows for both queries, and ratios and verdicts that follow from the printed numbers.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "cli/bench_text.h"
#include "tests/cli_support.h"

using namespace rayproof::cli;
using rayproof::testing::run_rayproof;
using rayproof::testing::write_file;

TEST(BenchTarget, VerdictFollowsThePrintedValue) {
  auto t = check_target("m", "robust / embree-robust (1 thread)", "primary", "closest", 0.59, 1.0, Goal::at_least, 2);
  EXPECT_EQ(t.value, "0.59");
  EXPECT_EQ(t.goal, "1.00");
  EXPECT_FALSE(t.met);
  EXPECT_EQ(t.verdict, "missed by 0.41 (41% of the goal)");
  // 0.996 prints as 1.00: met, as the reader sees it.
  t = check_target("m", "x", "", "", 0.996, 1.0, Goal::at_least, 2);
  EXPECT_EQ(t.value, "1.00");
  EXPECT_TRUE(t.met);
  EXPECT_EQ(t.verdict, "met");
  t = check_target("m", "x", "", "", 0.994, 1.0, Goal::at_least, 2);
  EXPECT_EQ(t.value, "0.99");
  EXPECT_EQ(t.verdict, "missed by 0.01 (1% of the goal)");
  // At most: build ratio and bytes; leaks against 0 have no percentage.
  t = check_target("m", "build", "", "", 1.2949, 1.0, Goal::at_most, 2);
  EXPECT_EQ(t.verdict, "missed by 0.29 (29% of the goal)");
  t = check_target("m", "build", "", "", 0.8, 1.0, Goal::at_most, 2);
  EXPECT_EQ(t.verdict, "met");
  t = check_target("m", "bytes", "", "", 64.04, 64.0, Goal::at_most, 1);
  EXPECT_EQ(t.value, "64.0");
  EXPECT_TRUE(t.met);
  t = check_target("m", "bytes", "", "", 64.1, 64.0, Goal::at_most, 1);
  EXPECT_EQ(t.verdict, "missed by 0.1 (0.16% of the goal)");
  t = check_target("m", "robust leaks", "", "", 186, 0.0, Goal::at_most, 0);
  EXPECT_EQ(t.verdict, "missed by 186");
  t = check_target("m", "scaling", "", "", 1.86, 1.9, Goal::at_least, 2);
  EXPECT_EQ(t.verdict, "missed by 0.04 (2.1% of the goal)");
}

TEST(BenchTarget, SpeedupsAboveTwoOnTwoThreadsAreNotJudged) {
  BenchTarget t = scaling_target("m", "robust 2 threads / 1 thread", "random", "any", 1.95);
  EXPECT_TRUE(t.met);
  EXPECT_EQ(t.verdict, "met");
  t = scaling_target("m", "robust 2 threads / 1 thread", "random", "any", 2.104);  // printed 2.10: judged
  EXPECT_EQ(t.value, "2.10");
  EXPECT_TRUE(t.met);
  t = scaling_target("m", "robust 2 threads / 1 thread", "random", "any", 2.96);
  EXPECT_EQ(t.value, "2.96");
  EXPECT_FALSE(t.met);
  EXPECT_EQ(t.verdict, "not judged: above 2.10, more than twice one thread's rate");
  t = scaling_target("m", "robust 2 threads / 1 thread", "random", "any", 1.5);
  EXPECT_EQ(t.verdict, "missed by 0.40 (21% of the goal)");
}

TEST(BenchTarget, TargetsFromRowsAndBuilds) {
  std::vector<BenchRow> rows;
  auto row = [&](const char* method, const char* rays, const char* query, double mrays, double scaled) {
    BenchRow r;
    r.mesh = "m", r.method = method, r.rays = rays, r.query = query, r.n = 10, r.mrays = mrays;
    if (scaled > 0) r.scaled_threads = 2, r.mrays_scaled = scaled;
    r.bytes = std::string(method) == "robust" ? 61.5 : -1;
    r.leaks = std::string(method) == "embree-robust" ? 186 : 0, r.leak_rays = 1000;
    rows.push_back(r);
  };
  for (const char* q : {"closest", "any"}) {
    row("robust", "primary", q, 5.0, 9.7);
    row("certified", "primary", q, 4.0, 7.0);
    row("float", "primary", q, 6.0, 12.0);
    row("embree", "primary", q, 8.0, 16.0);
    row("embree-robust", "primary", q, 4.0, 8.0);
  }
  const std::vector<BenchBuild> builds{{"m", 1, 0.03, 0.025}, {"m", 2, 0.02, 0.02}, {"n", 1, 0.5, -1}};
  const auto targets = bench_targets(rows, builds);
  std::map<std::string, const BenchTarget*> by;
  for (const auto& t : targets) by[t.what + "|" + t.query] = &t;
  ASSERT_TRUE(by.count("robust / embree-robust (1 thread)|closest"));
  EXPECT_EQ(by["robust / embree-robust (1 thread)|closest"]->value, "1.25");
  EXPECT_TRUE(by["robust / embree-robust (1 thread)|any"]->met);
  EXPECT_EQ(by["certified / embree-robust (1 thread)|closest"]->value, "1.00");
  EXPECT_EQ(by["float / embree (1 thread)|closest"]->verdict, "missed by 0.25 (25% of the goal)");
  EXPECT_EQ(by["robust 2 threads / 1 thread|closest"]->value, "1.94");
  EXPECT_EQ(by["certified 2 threads / 1 thread|any"]->verdict, "missed by 0.15 (7.9% of the goal)");
  EXPECT_EQ(by["build / Embree's build (1 thread)|"]->value, "1.20");
  EXPECT_FALSE(by["build / Embree's build (1 thread)|"]->met);
  EXPECT_TRUE(by["build / Embree's build (2 threads)|"]->met);
  EXPECT_TRUE(by["robust bytes per triangle|"]->met);
  EXPECT_EQ(by["robust leaks|"]->value, "0");
  EXPECT_TRUE(by["certified leaks|"]->met);
  // No Embree build on mesh n: no build target there; 2 queries x (3 ratios + 3 speed-ups) + 2 builds + bytes + 2 leaks.
  for (const auto& t : targets) EXPECT_EQ(t.mesh, "m");
  EXPECT_EQ(targets.size(), 2u * 6 + 2 + 1 + 2);
  // The table prints every verdict.
  const std::string table = targets_table(targets);
  for (const auto& t : targets) EXPECT_NE(table.find(t.verdict), std::string::npos);
}

TEST(BenchTarget, PacketRowsAreJudgedAgainstTheSamePath) {
  // Packet rows (primary rays) beside single ones: each ratio target takes the competitor's row of
  // the same path and names the path; speed-up targets stay single-ray ones; the table's ratio
  // column divides by embree-robust on the same path.
  std::vector<BenchRow> rows;
  auto row = [&](const char* method, const char* path, double mrays) {
    BenchRow r;
    r.mesh = "m", r.method = method, r.rays = "primary", r.query = "closest", r.path = path, r.n = 16, r.mrays = mrays;
    r.scaled_threads = 2, r.mrays_scaled = 1.9 * mrays;
    rows.push_back(r);
  };
  row("robust", "single", 3.0), row("robust", "packet8", 4.5);
  row("embree-robust", "single", 4.0), row("embree-robust", "packet8", 5.0), row("embree-robust", "packet16", 9.0);
  row("float", "packet8", 7.0), row("embree", "packet8", 6.0), row("embree", "single", 8.0);
  const auto targets = bench_targets(rows, {});
  std::map<std::string, const BenchTarget*> by;
  for (const auto& t : targets) by[t.what] = &t;
  ASSERT_TRUE(by.count("robust / embree-robust (1 thread)"));
  EXPECT_EQ(by["robust / embree-robust (1 thread)"]->value, "0.75");
  ASSERT_TRUE(by.count("robust / embree-robust (packet8, 1 thread)"));
  EXPECT_EQ(by["robust / embree-robust (packet8, 1 thread)"]->value, "0.90");
  EXPECT_EQ(by["robust / embree-robust (packet8, 1 thread)"]->verdict, "missed by 0.10 (10% of the goal)");
  ASSERT_TRUE(by.count("float / embree (packet8, 1 thread)"));
  EXPECT_EQ(by["float / embree (packet8, 1 thread)"]->value, "1.17");
  EXPECT_TRUE(by["float / embree (packet8, 1 thread)"]->met);
  EXPECT_FALSE(by.count("float / embree (1 thread)"));  // no single float row
  // One speed-up target: robust's single row (packet rows have none).
  EXPECT_EQ(std::count_if(targets.begin(), targets.end(), [](const BenchTarget& t) { return t.what.find("2 threads") != std::string::npos; }), 1);
  EXPECT_EQ(targets.size(), 4u);
  const std::string table = bench_table(rows);
  EXPECT_NE(table.find("packet8"), std::string::npos);
  // robust packet8: 4.5 / 5.0 (embree-robust packet8), not / 4.0 or / 9.0.
  const auto line = [&](const std::string& method, const std::string& path) {
    for (std::size_t p = 0; p < table.size();) {
      const std::size_t e = table.find('\n', p);
      const std::string l = table.substr(p, e - p);
      if (l.find(" " + method + " ") != std::string::npos && l.find(" " + path + " ") != std::string::npos) return l;
      p = e + 1;
    }
    return std::string();
  };
  EXPECT_NE(line("robust", "packet8").find(" 0.900 "), std::string::npos) << table;
  EXPECT_NE(line("robust", "single").find(" 0.750 "), std::string::npos) << table;
  EXPECT_NE(line("embree-robust", "packet16").find(" 1.000 "), std::string::npos) << table;
  EXPECT_NE(line("float", "packet8").find(" - "), std::string::npos) << table;  // no embree-robust float row: '-'
  // JSON: the path field and the same-path ratio.
  const auto j = nlohmann::json::parse(bench_json(rows, targets));
  EXPECT_EQ(j[1]["path"], "packet8");
  EXPECT_NEAR(j[1]["ratio_to_embree_robust"].get<double>(), 0.9, 1e-9);
}

/// Slow rates (a sanitizer build's, around 10^-3 Mrays/s, beside an unsanitized Embree) keep all
/// their digits in the JSON, so a ratio recomputed from the printed rates matches the printed ratio to
/// its 3 decimals whatever the timing (rates printed to 4 decimals made 0.0012 / 0.0100 of 0.00118 /
/// 0.00996, and the check failed on slow machines).
TEST(BenchJson, RatesKeepEveryDigitSoPrintedRatiosRecompute) {
  std::vector<BenchRow> rows;
  auto row = [&](const char* method, double mrays) {
    BenchRow r;
    r.mesh = "m", r.method = method, r.rays = "random", r.n = 300, r.mrays = mrays;
    r.scaled_threads = 2, r.mrays_scaled = 1.9371 * mrays;
    rows.push_back(r);
  };
  row("robust", 0.0011849), row("embree-robust", 0.0099617), row("certified", 3.1e-5), row("float", 148.3);
  const auto j = nlohmann::json::parse(bench_json(rows, {}));
  ASSERT_EQ(j.size(), 4u);
  EXPECT_EQ(j[0]["mrays_per_s"].get<double>(), 0.0011849);
  EXPECT_EQ(j[2]["mrays_per_s"].get<double>(), 3.1e-5);
  for (const auto& x : j) {
    const double printed = x["ratio_to_embree_robust"].get<double>();
    EXPECT_LE(std::abs(printed - x["mrays_per_s"].get<double>() / j[1]["mrays_per_s"].get<double>()), 5e-4 * (1 + 1e-9))
        << x["method"];
    EXPECT_LE(std::abs(x["scaling"].get<double>() - x["mrays_per_s_scaled"].get<double>() / x["mrays_per_s"].get<double>()),
              5e-4 * (1 + 1e-9))
        << x["method"];
  }
}

TEST(BenchText, Avx2RatioLinesFromKnownRates) {
  // embree-avx2 beside embree on two paths, embree-robust-avx2 beside embree-robust on one; a
  // packet16 row without an avx2 twin and an avx2 row without a default twin give nothing.
  std::vector<BenchRow> rows;
  auto row = [&](const char* mesh, const char* method, const char* rays, const char* query, const char* path, double mrays) {
    BenchRow r;
    r.mesh = mesh, r.method = method, r.rays = rays, r.query = query, r.path = path, r.n = 100, r.mrays = mrays;
    rows.push_back(r);
  };
  row("bunny00.off", "embree", "primary", "closest", "single", 16.5963);
  row("bunny00.off", "embree", "primary", "closest", "packet8", 22.6781);
  row("bunny00.off", "embree", "primary", "closest", "packet16", 24.925);
  row("bunny00.off", "embree-robust", "random", "any", "single", 6.291);
  row("bunny00.off", "embree-avx2", "primary", "closest", "single", 15.3214);
  row("bunny00.off", "embree-avx2", "primary", "closest", "packet8", 23.0);
  row("bunny00.off", "embree-robust-avx2", "random", "any", "single", 5.0334);
  row("other.off", "embree-avx2", "primary", "closest", "single", 3.0);  // no embree row on other.off
  const std::string text = avx2_ratio_lines(rows);
  // 15.321 / 16.596 = 0.9232 and 23.000 / 22.678 = 1.0142, 5.033 / 6.291 = 0.8000: the printed rates' ratios.
  EXPECT_EQ(text,
            "bunny00.off primary closest: embree-avx2 / embree 15.321 / 16.596 = 0.92 (single), 23.000 / 22.678 = 1.01 (packet8)\n"
            "bunny00.off random any: embree-robust-avx2 / embree-robust 5.033 / 6.291 = 0.80 (single)\n");
  // The ratio is of the rates as printed (slow rates, a sanitizer build's): 0.0144 / 0.0166 prints
  // 0.014 / 0.017 = 0.82, not the unprinted 0.87.
  rows = {};
  row("m", "embree", "random", "closest", "single", 0.0166);
  row("m", "embree-avx2", "random", "closest", "single", 0.0144);
  EXPECT_EQ(avx2_ratio_lines(rows), "m random closest: embree-avx2 / embree 0.014 / 0.017 = 0.82 (single)\n");
  // A default rate printed as 0.000: no ratio.
  rows[0].mrays = 0.0004;
  EXPECT_EQ(avx2_ratio_lines(rows), "m random closest: embree-avx2 / embree 0.014 / 0.000 = - (single)\n");
  // No avx2 rows: nothing.
  rows.pop_back();
  EXPECT_EQ(avx2_ratio_lines(rows), "");
}

TEST(BenchText, IsaLinesForEachSide) {
  BenchIsa isa;
  EXPECT_EQ(isa_lines(isa), "");  // no scene ran
  isa.nodes = "avx2-8wide", isa.leaves = "avx2", isa.cpu = {{"avx2", true}, {"fma", true}, {"avx512f", true}};
  EXPECT_EQ(isa_lines(isa), "isa: rayproof nodes avx2-8wide, leaves avx2 (cpu: avx2 fma avx512f)\n");
  isa.nodes = "sse-4wide", isa.leaves = "sse", isa.cpu = {{"avx2", false}, {"fma", true}, {"avx512f", false}};
  EXPECT_EQ(isa_lines(isa), "isa: rayproof nodes sse-4wide, leaves sse (cpu: fma, no avx2 avx512f)\n");
  isa.cpu = {{"avx2", false}};
  EXPECT_EQ(isa_lines(isa), "isa: rayproof nodes sse-4wide, leaves sse (cpu: no avx2)\n");
  isa.cpu = {{"avx2", true}, {"fma", true}, {"avx512f", true}};
  isa.nodes = "avx2-8wide", isa.leaves = "avx2";
  isa.competitors = {{"embree", "avx512", "avx512::K1", "how"},
                     {"cgal-epick", "", "", ""},  // reports none: left out
                     {"embree-avx2", "avx2", "avx2::K1", "how"}};
  EXPECT_EQ(isa_lines(isa),
            "isa: rayproof nodes avx2-8wide, leaves avx2 (cpu: avx2 fma avx512f)\n"
            "isa: embree avx512, embree-avx2 avx2 (how: embree avx512::K1, embree-avx2 avx2::K1)\n");
  const auto j = nlohmann::json::parse(bench_json({}, {}, &isa));
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["isa"]["rayproof"]["nodes"], "avx2-8wide");
  EXPECT_EQ(j[0]["isa"]["rayproof"]["leaves"], "avx2");
  EXPECT_EQ(j[0]["isa"]["rayproof"]["cpu"]["avx512f"], true);
  ASSERT_EQ(j[0]["isa"]["competitors"].size(), 2u);
  EXPECT_EQ(j[0]["isa"]["competitors"][1]["name"], "embree-avx2");
  EXPECT_EQ(j[0]["isa"]["competitors"][1]["isa"], "avx2");
  EXPECT_EQ(j[0]["isa"]["competitors"][1]["kernel"], "avx2::K1");
  EXPECT_EQ(j[0]["isa"]["competitors"][1]["how"], "how");
}

namespace {
/// An octahedron, closed, as OFF.
std::string octahedron_off() {
  return "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
         "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";
}
}  // namespace

TEST(BenchCli, JsonRowsForBothQueriesAndTargetsFromThePrintedNumbers) {
  // Half a unit of the printed ratios' last decimal, plus the rounding of one division.
  constexpr double kHalfMilli = 5e-4 * (1 + 1e-9);
  const auto mesh = write_file("bench_octahedron.off", octahedron_off());
  const auto r = run_rayproof("bench " + mesh.string() +
                              " --json --threads 2 --repeat 1 --rays 300 --leak-rays 40 --width 16 --height 12"
                              " --methods float,robust,certified --competitors embree,embree-robust,cgal-epick");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.is_array());
  std::map<std::string, nlohmann::json> row;  // method/rays/query, then /path for packet rows
  std::vector<nlohmann::json> targets;
  nlohmann::json isa;
  for (const auto& x : j) {
    if (x.contains("target")) {
      targets.push_back(x);
      continue;
    }
    if (x.contains("isa")) {
      EXPECT_TRUE(isa.is_null()) << "two isa objects";
      isa = x["isa"];
      continue;
    }
    for (const char* f : {"method", "rays", "query", "path", "mesh", "ray_count", "threads", "mrays_per_s", "build_s",
                          "bytes_per_tri", "ratio_to_embree_robust", "leaks", "leak_rays", "scaling_threads",
                          "mrays_per_s_scaled", "scaling"})
      EXPECT_TRUE(x.contains(f)) << f;
    EXPECT_EQ(x["mesh"], "bench_octahedron.off");
    EXPECT_EQ(x["threads"], 1);
    const std::string path = x["path"];
    std::string key = x["method"].get<std::string>() + "/" + x["rays"].get<std::string>() + "/" + x["query"].get<std::string>();
    if (path != "single") {
      // Packets: primary rays only, ours eight at a time, Embree's 8 and 16.
      EXPECT_TRUE(path == "packet8" || path == "packet16") << path;
      EXPECT_EQ(x["rays"], "primary");
      EXPECT_EQ(x["ray_count"], 16 * 12);
      EXPECT_GT(x["mrays_per_s"].get<double>(), 0.0) << key;
      key += "/" + path;
    }
    EXPECT_FALSE(row.count(key)) << key;
    row[key] = x;
  }
  const bool embree = row.count("embree-robust/primary/closest") > 0;
  std::vector<std::string> methods{"float", "robust", "certified", "cgal-epick"};
  if (embree) methods.insert(methods.end(), {"embree", "embree-robust"});
  for (const auto& m : methods)
    for (const char* rays : {"primary", "random"})
      for (const char* q : {"closest", "any"}) {
        const std::string key = m + "/" + rays + "/" + q;
        ASSERT_TRUE(row.count(key)) << key;
        const auto& x = row[key];
        EXPECT_EQ(x["ray_count"], std::string(rays) == "primary" ? 16 * 12 : 300) << key;
        EXPECT_GT(x["mrays_per_s"].get<double>(), 0.0) << key;
        EXPECT_EQ(x["scaling_threads"], 2) << key;
        // Rates are printed in full (shortest round-trip), ratios to 3 decimals: the recomputed ratio may
        // differ from the printed one by half a unit of the third decimal, whatever the timing.
        EXPECT_NEAR(x["scaling"].get<double>(), x["mrays_per_s_scaled"].get<double>() / x["mrays_per_s"].get<double>(), kHalfMilli) << key;
        if (m == "robust" || m == "certified") {
          EXPECT_EQ(x["leaks"], 0) << key;
          EXPECT_GT(x["leak_rays"].get<int>(), 0) << key;
        }
        if (embree) {
          const double er = row[std::string("embree-robust/") + rays + "/" + q]["mrays_per_s"].get<double>();
          EXPECT_NEAR(x["ratio_to_embree_robust"].get<double>(), x["mrays_per_s"].get<double>() / er, kHalfMilli) << key;
        } else {
          EXPECT_TRUE(x["ratio_to_embree_robust"].is_null()) << key;
        }
      }
  // Packet rows: every compiled method ours, both queries; robust and certified leak nothing there.
  for (const std::string m : {"float", "robust", "certified"})
    for (const char* q : {"closest", "any"}) {
      const std::string key = m + "/primary/" + q + "/packet8";
      ASSERT_TRUE(row.count(key)) << key;
      if (m != "float") {
        EXPECT_EQ(row[key]["leaks"], 0) << key;
      }
      if (embree) {
        const double er = row[std::string("embree-robust/primary/") + q + "/packet8"]["mrays_per_s"].get<double>();
        EXPECT_NEAR(row[key]["ratio_to_embree_robust"].get<double>(), row[key]["mrays_per_s"].get<double>() / er, kHalfMilli)
            << key;
      }
    }
  if (embree) {
    EXPECT_TRUE(row.count("embree-robust/primary/any/packet8"));
  }
  // Which instruction set each side ran: ours always, Embree's as it reports them.
  ASSERT_TRUE(isa.is_object()) << r.out;
  EXPECT_TRUE(isa["rayproof"]["nodes"] == "avx2-8wide" || isa["rayproof"]["nodes"] == "sse-4wide") << isa;
  EXPECT_TRUE(isa["rayproof"]["cpu"].contains("avx2"));
  std::set<std::string> reported;
  for (const auto& c : isa["competitors"]) reported.insert(c["name"].get<std::string>());
  const std::set<std::string> expected = embree ? std::set<std::string>{"embree", "embree-robust"} : std::set<std::string>{};
  EXPECT_EQ(reported, expected) << isa;
  // Targets: every verdict agrees with its printed value and goal.
  std::set<std::string> kinds;
  for (const auto& t : targets) {
    kinds.insert(t["target"].get<std::string>());
    const double v = t["value"].get<double>(), g = t["goal"].get<double>();
    const std::string what = t["target"];
    const bool at_most = what.find("build") != std::string::npos || what.find("bytes") != std::string::npos ||
                         what.find("leaks") != std::string::npos;
    if (what.find("2 threads / 1 thread") != std::string::npos && v > 2.1) {
      // An impossible speed-up (a disturbed timing) is not judged.
      EXPECT_FALSE(t["met"].get<bool>()) << what;
      EXPECT_EQ(t["verdict"].get<std::string>(), "not judged: above 2.10, more than twice one thread's rate") << what;
      continue;
    }
    EXPECT_EQ(t["met"].get<bool>(), at_most ? v <= g : v >= g) << what;
    EXPECT_EQ(t["verdict"].get<std::string>() == "met", t["met"].get<bool>()) << what;
  }
  EXPECT_TRUE(kinds.count("robust 2 threads / 1 thread"));
  EXPECT_TRUE(kinds.count("robust bytes per triangle"));
  EXPECT_TRUE(kinds.count("robust leaks"));
  EXPECT_TRUE(kinds.count("certified leaks"));
  if (embree) {
    EXPECT_TRUE(kinds.count("robust / embree-robust (1 thread)"));
    EXPECT_TRUE(kinds.count("certified / embree-robust (1 thread)"));
    EXPECT_TRUE(kinds.count("float / embree (1 thread)"));
    EXPECT_TRUE(kinds.count("build / Embree's build (1 thread)"));
    EXPECT_TRUE(kinds.count("build / Embree's build (2 threads)"));
    // A robust ratio target per ray set and query, its value the row's ratio as printed.
    for (const auto& t : targets)
      if (t["target"] == "robust / embree-robust (1 thread)") {
        const auto& x = row["robust/" + t["rays"].get<std::string>() + "/" + t["query"].get<std::string>()];
        EXPECT_NEAR(t["value"].get<double>(), x["ratio_to_embree_robust"].get<double>(), 0.0051);
      }
  }
}

TEST(BenchCli, TextTablesAndBadOptions) {
  const auto mesh = write_file("bench_octahedron2.off", octahedron_off());
  const auto r = run_rayproof("bench " + mesh.string() +
                              " --threads 1 --repeat 1 --rays 100 --leak-rays 20 --width 8 --height 8"
                              " --methods robust --competitors none");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* s : {"Mrays/s 1t", "BVH build", "Targets: speed against Embree", "robust leaks",
                        "robust bytes per triangle", "\nisa: rayproof "})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
  // No competitor: no competitor's isa line, no avx2 ratios.
  EXPECT_EQ(r.out.find("isa: embree"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("max_isa=avx2"), std::string::npos) << r.out;
  // One thread: no speed-up measured, no speed-up target.
  EXPECT_EQ(r.out.find("2 threads / 1 thread"), std::string::npos);
  EXPECT_NE(run_rayproof("bench " + mesh.string() + " --repeat 0").status, 0);
  EXPECT_NE(run_rayproof("bench " + mesh.string() + " --threads -1").status, 0);
  EXPECT_NE(run_rayproof("bench " + mesh.string() + " --width 0").status, 0);
}

TEST(BenchCli, EmbreeCappedAtAvx2BesideItsDefaultDevice) {
  const auto mesh = write_file("bench_octahedron3.off", octahedron_off());
  // An unknown name is an error before anything runs, naming the names it takes.
  const auto bad = run_rayproof("bench " + mesh.string() + " --competitors embree,embree-avx512 --repeat 1");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("unknown competitor 'embree-avx512'"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("embree-robust-avx2"), std::string::npos) << bad.err;
  EXPECT_EQ(bad.out, "");
  const auto r = run_rayproof("bench " + mesh.string() +
                              " --threads 1 --repeat 1 --rays 100 --leak-rays 20 --width 8 --height 8"
                              " --methods robust --competitors embree,embree-robust,embree-avx2,embree-robust-avx2");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\nisa: rayproof "), std::string::npos) << r.out;
  const bool embree = r.out.find(" embree-avx2 ") != std::string::npos;
  if (!embree) {
    EXPECT_EQ(r.out.find("isa: embree"), std::string::npos) << r.out;  // built without Embree
    return;
  }
  // Embree's line names every Embree competitor with its ISA, the capped ones at most avx2.
  const std::size_t at = r.out.find("\nisa: embree ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string line = r.out.substr(at + 1, r.out.find('\n', at + 1) - at - 1);
  for (const char* s : {"embree-avx2 avx2", "embree-robust-avx2 avx2", "verbose=3"})
    EXPECT_NE(line.find(s), std::string::npos) << s << " in " << line;
  // One ratio line per ray set, query and pair, with the rates the table printed.
  for (const char* pair : {"embree-avx2 / embree ", "embree-robust-avx2 / embree-robust "})
    for (const char* rq : {"primary closest", "primary any", "random closest", "random any"}) {
      const std::string head = std::string("bench_octahedron3.off ") + rq + ": " + pair;
      EXPECT_NE(r.out.find(head), std::string::npos) << head << "\n" << r.out;
    }
  EXPECT_NE(r.out.find("(packet8)"), std::string::npos) << r.out;
}

// The open meshes' first-batch line, from known timings: the best batch's time is the points over
// the printed rate, and "more than" is the difference of the two printed times.
TEST(BenchText, FirstBatchLineFromKnownTimings) {
  EXPECT_EQ(first_batch_line(0.16, 20000, 0.3333),
            "the first batch took 0.160 s, 0.100 s more than the best batch after it (0.060 s at 0.3333 Mpoints/s)");
  EXPECT_EQ(first_batch_line(0.05, 20000, 0.25),
            "the first batch took 0.050 s, no more than the best batch after it (0.080 s at 0.2500 Mpoints/s)");
  EXPECT_EQ(first_batch_line(0.08, 20000, 0.25),
            "the first batch took 0.080 s, no more than the best batch after it (0.080 s at 0.2500 Mpoints/s)");
  EXPECT_EQ(first_batch_line(1.0, 20000, 0), "");
}
