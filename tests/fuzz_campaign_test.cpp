// The differential fuzz campaign: reproducible counts, findings, minimization, broken promises.
#include "verify/fuzz_campaign.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "cli_support.h"
#include "verify/exact_method.h"

using namespace rayproof;

namespace {
std::vector<const gen::Family*> some_families() {
  return {gen::find_family("tri_edge"), gen::find_family("sph_tangent_exact"), gen::find_family("box_graze"),
          gen::find_family("plane_near_parallel")};
}

/// A method that claims exactness but rounds every t to float: a broken promise to find.
Method sloppy_certified() {
  MethodRegistry reg;
  register_fast_methods(reg);
  Method m = *reg.find("double");
  m.name = "certified-sloppy";
  m.promises = exact_promises();  // it claims what certified claims
  m.classify = [](const io::Case& c) {
    io::CaseResult r = verify::exact_classify(c);
    if (r.t) r.t = static_cast<double>(static_cast<float>(*r.t));
    return r;
  };
  return m;
}
}  // namespace

TEST(FuzzCampaign, SameSeedSameCountsWhateverTheThreads) {
  MethodRegistry reg;
  register_fast_methods(reg);
  verify::FuzzOptions opt;
  opt.methods = {reg.find("float"), reg.find("double")};
  opt.families = some_families();
  opt.max_cases = 2000;
  opt.seed = 11;
  opt.batch = 50;
  const auto a = verify::run_fuzz(opt);
  opt.jobs = 2;
  const auto b = verify::run_fuzz(opt);
  EXPECT_EQ(a.cases, b.cases);
  EXPECT_GE(a.cases, 2000u);
  EXPECT_EQ(a.mismatches, b.mismatches);
  std::size_t float_bad = 0;
  for (const auto& [k, n] : a.mismatches)
    if (k.first == "float") float_bad += n;
  EXPECT_GT(float_bad, 0u) << "float must disagree somewhere on exact edges and tangents";
  EXPECT_TRUE(a.broken_promises().empty());
  opt.seed = 12;
  const auto c = verify::run_fuzz(opt);
  EXPECT_NE(a.mismatches, c.mismatches);
}

TEST(FuzzCampaign, BrokenPromiseIsReportedAndMinimized) {
  const Method bad = sloppy_certified();
  verify::FuzzOptions opt;
  opt.methods = {&bad};
  opt.families = {gen::find_family("sph_generic")};
  opt.max_cases = 200;
  opt.batch = 100;
  const auto res = verify::run_fuzz(opt);
  ASSERT_EQ(res.broken_promises(), std::vector<std::string>{"certified-sloppy"});
  ASSERT_FALSE(res.findings.empty());
  const auto& f = res.findings.front();
  EXPECT_TRUE(f.minimized);
  EXPECT_GT(f.ulps, 1u);
  // The minimized case still disagrees, and its fields carry few significant bits.
  int short_fields = 0;
  for (int i = 0; i < io::field_count(f.input.kind); ++i) {
    const double x = f.input.v[static_cast<std::size_t>(i)];
    if (x == 0 || std::ldexp(x, 40 - std::ilogb(x)) == std::nearbyint(std::ldexp(x, 40 - std::ilogb(x)))) ++short_fields;
  }
  EXPECT_EQ(short_fields, io::field_count(f.input.kind));
}

TEST(FuzzCli, CampaignPrintsSummaryAndReproducer) {
  const auto dir = rayproof::testing::scratch_dir() / "findings";
  const auto r = rayproof::testing::run_rayproof(
      "fuzz --cases 3000 --seed 5 --methods float,certified --families tri_vertex,disk_rim --out " + dir.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("reproduce: rayproof fuzz --seed 5 --cases"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("certified        (all)"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir / "float")) << "float findings are written";
  EXPECT_FALSE(std::filesystem::exists(dir / "certified")) << "certified has no finding";
  const auto again = rayproof::testing::run_rayproof(
      "fuzz --cases 3000 --seed 5 --methods float,certified --families tri_vertex,disk_rim --jobs 2 --out " + dir.string());
  EXPECT_EQ(again.out.substr(0, again.out.find("\n\n")), r.out.substr(0, r.out.find("\n\n")));
}

TEST(FuzzCampaign, TalliesAndFindingsDoNotGrowWithTheCaseCount) {
  // A campaign once kept every t error and every round until the end (~137 bytes per case).
  // What it holds now is fixed: tallies of fixed size, findings capped per method x family.
  MethodRegistry reg;
  register_fast_methods(reg);
  verify::FuzzOptions opt;
  opt.methods = {reg.find("float"), reg.find("double")};
  opt.families = some_families();
  opt.seed = 21;
  opt.jobs = 2;
  opt.keep_per_group = 5;
  opt.minimize_per_group = 1;
  auto held = [](const verify::FuzzResult& r) {
    std::size_t n = 0;
    for (const auto& [k, t] : r.stats) n += t.bytes();
    return n;
  };
  opt.max_cases = 10000;
  const auto small = verify::run_fuzz(opt);
  opt.max_cases = 100000;
  const auto large = verify::run_fuzz(opt);
  ASSERT_GE(large.cases, 100000u);
  const std::size_t groups = opt.methods.size() * opt.families.size();
  EXPECT_EQ(large.stats.size(), groups);
  EXPECT_EQ(small.stats.size(), groups);
  // Each tally has its fixed size (the histogram's counters are allocated whole), so ten times the
  // cases hold the same bytes, but for the family name of each tally's worst case (at most 64); keeping
  // the t errors would add 8 bytes per case and method (over 1 MB here).
  const std::size_t bound = groups * (sizeof(verify::FuzzTally) + 8 * verify::UlpHistogram::kBuckets + 64);
  EXPECT_LE(held(large), bound);
  EXPECT_LE(held(large), held(small) + groups * 64);
  EXPECT_LE(held(small), held(large) + groups * 64);
  std::size_t t_errors = 0, mismatches = 0;
  for (const auto& [k, t] : large.stats) t_errors += t.ulps.count();
  for (const auto& [k, n] : large.mismatches) mismatches += n;
  EXPECT_GT(t_errors, 100000u) << "the histograms count every t error";
  EXPECT_GT(mismatches, large.findings.size()) << "more mismatches than kept findings: the cap is exercised";
  EXPECT_LE(large.findings.size(), groups * opt.keep_per_group);
  EXPECT_LE(small.findings.size(), groups * opt.keep_per_group);
}

TEST(FuzzCli, ProgressInALogIsOneLineEachWithoutCarriageReturns) {
  // stderr is a file here (not a terminal): one newline-terminated line per --progress-seconds.
  const auto dir = rayproof::testing::scratch_dir() / "progress";
  const auto r = rayproof::testing::run_rayproof("fuzz --seconds 1.5 --progress-seconds 0.1 --methods float --families "
                                                 "tri_edge,box_graze --out " + dir.string());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << "no carriage return in a log";
  std::size_t lines = 0;
  for (std::size_t p = 0; (p = r.err.find("cases/s; mismatches: float=", p)) != std::string::npos; ++p) ++lines;
  EXPECT_GE(lines, 4u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), static_cast<std::ptrdiff_t>(lines)) << r.err;
  // The summary gives the speed per job and per CPU second.
  EXPECT_NE(r.out.find("cases/s on 1 job, "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" per CPU second ("), std::string::npos) << r.out;
}
