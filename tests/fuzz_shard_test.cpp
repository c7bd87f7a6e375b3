// Sharded fuzz campaigns: the shards of a seeded --cases campaign, run as separate
// processes, merge to exactly the counts and the table of the unsharded run; bad shards and foreign
// summaries get clear errors.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "cli/fuzz_summary.h"
#include "registry/registry.h"
#include "cli_support.h"

using namespace rayproof;
using rayproof::testing::run_rayproof;
using rayproof::testing::scratch_dir;
using rayproof::testing::slurp;

namespace {
const std::string kCampaign =
    "--seed 7 --cases 2500 --methods float,robust,certified --families tri_edge,tri_vertex,sph_tangent_exact,box_graze";

/// The table: the lines up to the first blank line.
std::string table_of(const std::string& out) { return out.substr(0, out.find("\n\n") + 1); }
}  // namespace

TEST(FuzzShard, ShardsAreDisjointAndAddUpInTheEngine) {
  verify::FuzzOptions opt;
  for (const char* m : {"float", "robust"}) opt.methods.push_back(registry::all_methods().find(m));
  for (const char* f : {"tri_edge", "plane_exact"}) opt.families.push_back(gen::find_family(f));
  opt.max_cases = 700;  // 6 rounds of 2 x 64 cases
  opt.seed = 12;
  const auto whole = verify::run_fuzz(opt);
  ASSERT_EQ(whole.rounds, 6u);
  verify::FuzzTally sum;
  std::size_t rounds = 0, cases = 0, mismatches = 0, whole_mismatches = 0;
  std::vector<std::size_t> seen_rounds;
  for (std::size_t k = 0; k < 4; ++k) {  // 4 shards of 6 rounds: 2, 2, 1, 1
    opt.shard_index = k, opt.shard_count = 4;
    const auto part = verify::run_fuzz(opt);
    EXPECT_EQ(part.rounds, k < 2 ? 2u : 1u) << k;
    rounds += part.rounds, cases += part.cases;
    for (const auto& [key, st] : part.stats) sum.merge(st);
    for (const auto& [key, n] : part.mismatches) mismatches += n;
    for (const auto& f : part.findings) {
      EXPECT_EQ(f.round % 4, k);
      seen_rounds.push_back(f.round);
    }
  }
  verify::FuzzTally all;
  for (const auto& [key, st] : whole.stats) all.merge(st);
  for (const auto& [key, n] : whole.mismatches) whole_mismatches += n;
  EXPECT_EQ(rounds, whole.rounds);
  EXPECT_EQ(cases, whole.cases);
  EXPECT_EQ(mismatches, whole_mismatches);
  EXPECT_EQ(sum.counts.cases, all.counts.cases);
  EXPECT_EQ(sum.counts.false_miss, all.counts.false_miss);
  EXPECT_EQ(sum.counts.wrong_hit_class, all.counts.wrong_hit_class);
  EXPECT_EQ(sum.ulps, all.ulps);  // the histograms, bucket for bucket, and the exact min and max
  EXPECT_GT(all.ulps.count(), 0u);
  EXPECT_GT(whole_mismatches, 0u);  // float loses edge hits: the sums compare something
}

TEST(FuzzShard, MergeOfShardProcessesEqualsTheSingleRun) {
  const auto dir = scratch_dir() / "shards";
  std::filesystem::create_directories(dir);
  const std::string d = dir.string();
  auto single = run_rayproof("fuzz " + kCampaign + " --out " + d + "/f0 --summary " + d + "/single.json");
  ASSERT_EQ(single.status, 0) << single.err;
  // Three shards as concurrent processes, as a job array would run them.
  std::string cmd;
  for (int k = 1; k <= 3; ++k)
    cmd += fmt::format("{} fuzz {} --shard {}/3 --out {}/f{} --summary {}/s{}.json >{}/o{}.txt 2>&1 & ", RAYPROOF_BIN,
                       kCampaign, k, d, k, d, k, d, k);
  ASSERT_EQ(std::system((cmd + "wait").c_str()), 0);
  auto merged = run_rayproof("fuzz merge " + d + "/s3.json " + d + "/s1.json " + d + "/s2.json --summary " + d +
                             "/merged.json");
  ASSERT_EQ(merged.status, 0) << merged.err;
  EXPECT_EQ(table_of(merged.out), table_of(single.out));
  EXPECT_NE(merged.out.find("from 3 shards"), std::string::npos);
  const auto a = nlohmann::json::parse(slurp(dir / "single.json"));
  const auto b = nlohmann::json::parse(slurp(dir / "merged.json"));
  EXPECT_EQ(a["stats"], b["stats"]);
  EXPECT_EQ(a["cases"], b["cases"]);
  EXPECT_EQ(a["rounds"], b["rounds"]);
  EXPECT_GT(a["cases"].get<int>(), 2400);

  // Errors: a shard missing, a shard twice, a summary of another campaign, bad K/N, foreign files.
  auto missing = run_rayproof("fuzz merge " + d + "/s1.json " + d + "/s2.json");
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("lacks shard 3"), std::string::npos) << missing.err;
  auto twice = run_rayproof("fuzz merge " + d + "/s1.json " + d + "/s1.json " + d + "/s2.json " + d + "/s3.json");
  EXPECT_EQ(twice.status, 2);
  EXPECT_NE(twice.err.find("shard 1/3 is in both"), std::string::npos) << twice.err;
  auto other = run_rayproof("fuzz --seed 8 --cases 2500 --methods float,robust,certified --families "
                            "tri_edge,tri_vertex,sph_tangent_exact,box_graze --shard 2/3 --out " + d + "/g --summary " +
                            d + "/other.json");
  ASSERT_EQ(other.status, 0) << other.err;
  auto mixed = run_rayproof("fuzz merge " + d + "/s1.json " + d + "/other.json " + d + "/s3.json");
  EXPECT_EQ(mixed.status, 2);
  EXPECT_NE(mixed.err.find("different campaigns (seed 7 and 8)"), std::string::npos) << mixed.err;
  auto unsharded = run_rayproof("fuzz merge " + d + "/s1.json " + d + "/single.json");
  EXPECT_EQ(unsharded.status, 2);
  EXPECT_NE(unsharded.err.find("3 and 1 shards"), std::string::npos) << unsharded.err;
  for (const char* k : {"0/3", "4/3", "3", "a/b", "1/0", "2/3x"}) {
    auto r = run_rayproof(std::string("fuzz --cases 10 --shard ") + k);
    EXPECT_EQ(r.status, 2) << k;
    EXPECT_NE(r.err.find("--shard wants K/N"), std::string::npos) << k << r.err;
  }
  const auto junk = rayproof::testing::write_file("junk.json", "{\"rows\": []}");
  auto j = run_rayproof("fuzz merge " + junk.string());
  EXPECT_EQ(j.status, 2);
  EXPECT_NE(j.err.find("not a rayproof fuzz summary"), std::string::npos) << j.err;
}

TEST(FuzzShard, ParseShard) {
  EXPECT_EQ(cli::parse_shard("1/1"), std::make_pair(std::size_t{0}, std::size_t{1}));
  EXPECT_EQ(cli::parse_shard("8/8"), std::make_pair(std::size_t{7}, std::size_t{8}));
  for (const char* bad : {"", "/", "1/", "/2", "0/1", "2/1", "-1/2", "1/2/3", " 1/2", "1/1000001"})
    EXPECT_FALSE(cli::parse_shard(bad).has_value()) << bad;
}

namespace {
verify::FuzzTally tally_of(const std::vector<std::pair<std::uint64_t, std::uint64_t>>& ulps, std::size_t cases) {
  verify::FuzzTally t;
  t.counts.cases = cases;
  for (const auto& [u, n] : ulps) t.ulps.add(u, n);
  return t;
}
}  // namespace

TEST(FuzzShard, TableSaysWhichPercentilesAreBucketBounds) {
  const std::vector<std::string> methods{"m"}, families{"a", "b"};
  verify::FuzzTallies st;
  std::map<std::pair<std::string, std::string>, std::size_t> mm{{{"m", "a"}, 0}, {{"m", "b"}, 0}};
  st[{"m", "a"}] = tally_of({{0, 98}, {1000, 1}, {5000, 1}}, 100);  // p99: rank 99, the bucket [1000, 1003]
  st[{"m", "b"}] = tally_of({{3, 10}}, 10);
  const std::string t = cli::fuzz_table(methods, families, st, mm);
  EXPECT_NE(t.find("m                a                              100          0    0.0000         0         0       <=1003         5000  none made\n"),
            std::string::npos) << t;
  EXPECT_NE(t.find("m                b                               10          0    0.0000         0         3            3            3  none made\n"),
            std::string::npos) << t;
  // (all): 110 values, 98 zeros, 10 threes: p50 = 0, p99 (rank 109) in [1000, 1003], max 5000.
  EXPECT_NE(t.find("m                (all)                          110          0    0.0000         0         0       <=1003         5000  none made\n"),
            std::string::npos) << t;
  EXPECT_NE(t.find("\"<=N\": the percentile lies in a histogram bucket whose upper bound is N"), std::string::npos) << t;
  EXPECT_NE(t.find("at most 0.78% below N; values below 256 are exact"), std::string::npos) << t;
  // All exact: no note about buckets.
  st[{"m", "a"}] = tally_of({{0, 98}, {2, 2}}, 100);
  const std::string exact = cli::fuzz_table(methods, families, st, mm);
  EXPECT_EQ(exact.find("<="), std::string::npos) << exact;
  EXPECT_NE(exact.find("the max is exact"), std::string::npos) << exact;
  EXPECT_EQ(cli::quantile_text({~0ull, ~0ull}), "NaN t");
  EXPECT_EQ(cli::quantile_text({1000, 1003}), "<=1003");
  EXPECT_EQ(cli::speed_text(300000, 2.0, 4.0, 2),
            "300000 cases in 2.0 s: 150000 cases/s on 2 jobs, 75000 per job; 75000 per CPU second (4.0 CPU s)");
  EXPECT_EQ(cli::speed_text(100, 1.0, 0.0, 1), "100 cases in 1.0 s: 100 cases/s on 1 job, 100 per job");
}

TEST(FuzzShard, SummaryJsonCarriesTheHistogramsExactly) {
  cli::FuzzSummary s;
  s.campaign.methods = {"m"}, s.campaign.families = {"a"};
  s.rounds = 3, s.cases = 200, s.seconds = 1.5, s.cpu_seconds = 2.5;
  auto t = tally_of({{0, 50}, {7, 3}, {300, 2}, {1ull << 40, 1}, {~0ull, 4}}, 200);
  t.bary_count = 2, t.bary_max = 0.125;
  s.stats[{"m", "a"}] = t;
  s.mismatches[{"m", "a"}] = 4;
  std::string error;
  const auto back = cli::summary_from_json(cli::to_json(s), "s.json", error);
  ASSERT_TRUE(back) << error;
  const auto& b = back->stats.at({"m", "a"});
  EXPECT_EQ(b.ulps, t.ulps);
  EXPECT_EQ(b.ulps.max(), ~0ull);
  EXPECT_EQ(b.bary_count, 2u);
  EXPECT_EQ(b.bary_max, 0.125);
  EXPECT_EQ(back->cpu_seconds, 2.5);
  EXPECT_EQ(cli::to_json(*back), cli::to_json(s));
  // A bucket that is not one, or counts beyond the cases, are malformed.
  auto bad = nlohmann::json::parse(cli::to_json(s));
  bad["stats"][0]["ulp_buckets"][2][0] = 301;
  EXPECT_FALSE(cli::summary_from_json(bad.dump(), "bad.json", error));
  EXPECT_NE(error.find("bad.json: malformed summary (a t error bucket is not a bucket)"), std::string::npos) << error;
  bad = nlohmann::json::parse(cli::to_json(s));
  bad["stats"][0]["cases"] = 10;
  EXPECT_FALSE(cli::summary_from_json(bad.dump(), "bad.json", error));
  // A version 1 summary (exact [value, count] pairs) still reads.
  auto v1 = nlohmann::json::parse(cli::to_json(s));
  v1["rayproof_fuzz_summary"] = 1;
  auto& row = v1["stats"][0];
  row.erase("ulp_buckets"), row.erase("ulp_min"), row.erase("ulp_max"), row.erase("bary_count"), row.erase("bary_error_max");
  row["ulps"] = nlohmann::json::array({{0, 50}, {7, 3}, {300, 2}, {1ull << 40, 1}, {~0ull, 4}});
  row["bary_errors"] = {0.0625, 0.125};
  const auto old = cli::summary_from_json(v1.dump(), "v1.json", error);
  ASSERT_TRUE(old) << error;
  EXPECT_EQ(old->stats.at({"m", "a"}).ulps, t.ulps);
  EXPECT_EQ(old->stats.at({"m", "a"}).bary_max, 0.125);
}
