// Sharded fuzz campaigns (issue 11, part 5): the shards of a seeded --cases campaign, run as separate
// processes, merge to exactly the counts and the table of the unsharded run; bad shards and foreign
// summaries get clear errors.
#include <gtest/gtest.h>

#include <fmt/core.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "cli/fuzz_summary.h"
#include "cli/registry.h"
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
  for (const char* m : {"float", "robust"}) opt.methods.push_back(cli::all_methods().find(m));
  for (const char* f : {"tri_edge", "plane_exact"}) opt.families.push_back(gen::find_family(f));
  opt.max_cases = 700;  // 6 rounds of 2 x 64 cases
  opt.seed = 12;
  const auto whole = verify::run_fuzz(opt);
  ASSERT_EQ(whole.rounds, 6u);
  verify::Stats sum;
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
  verify::Stats all;
  for (const auto& [key, st] : whole.stats) all.merge(st);
  for (const auto& [key, n] : whole.mismatches) whole_mismatches += n;
  EXPECT_EQ(rounds, whole.rounds);
  EXPECT_EQ(cases, whole.cases);
  EXPECT_EQ(mismatches, whole_mismatches);
  EXPECT_EQ(sum.cases, all.cases);
  EXPECT_EQ(sum.false_miss, all.false_miss);
  EXPECT_EQ(sum.wrong_hit_class, all.wrong_hit_class);
  std::sort(sum.ulps.begin(), sum.ulps.end());
  std::sort(all.ulps.begin(), all.ulps.end());
  EXPECT_EQ(sum.ulps, all.ulps);
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
