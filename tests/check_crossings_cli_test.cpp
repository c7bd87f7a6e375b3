// rayproof check --crossings: programs speaking the all-hits line protocol, judged on a mesh file.
// The numpy Möller–Trumbore example is caught (shared edges and vertices reported twice or missed,
// silhouettes reported as crossings); the example passing the rays to rayproof's own crossings (the
// Python module) has no finding; crashes, hangs and unreadable answers are reported and the run
// goes on; the JSON carries every counter and the cost ratio.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "cli_support.h"
#include "judge_report_support.h"

namespace rayproof {
namespace {

using testing::run_rayproof;
using testing::write_file;

const std::string& kCube = testing::kUnitCubeOff;

std::string example(const char* name) { return std::string(RAYPROOF_DATA_DIR) + "/../examples/crossings/" + name; }

std::size_t count_of(const std::string& out, const std::string& fn, const std::string& key) {
  return testing::summary_count(out, "function '" + fn + "'", key);
}

TEST(CheckCrossingsCli, NumpyExampleIsCaughtAndRayproofsOwnIsNot) {
  if (!testing::have_numpy()) GTEST_SKIP() << "/usr/bin/python3 has no numpy";
  const auto mesh = write_file("cube.off", kCube);
  const auto r = run_rayproof("check --crossings 'np=/usr/bin/python3 " + example("numpy_crossings.py") + "' --mesh " +
                              mesh.string() + " --crossings-rays 200");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_GT(count_of(r.out, "np", "duplicates") + count_of(r.out, "np", "missing"), 0u) << r.out;
  EXPECT_EQ(count_of(r.out, "np", "invalid_hit"), 0u) << r.out;
  EXPECT_EQ(count_of(r.out, "np", "failures"), 0u) << r.out;
  EXPECT_NE(r.out.find(" set=leak mesh=" + mesh.string() + " ray "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("function 'np' differs from exact on"), std::string::npos) << r.out;
  const std::string module = std::string(RAYPROOF_PYTHON_MODULE_DIR);
  if (!std::filesystem::exists(module)) GTEST_SKIP() << "the Python module is not built";
  const auto e = run_rayproof("check --crossings 'own=PYTHONPATH=" + module + " /usr/bin/python3 " +
                              example("rayproof_crossings.py") + "' --mesh " + mesh.string() + " --crossings-rays 200");
  EXPECT_EQ(e.status, 0) << e.err << e.out;
  EXPECT_LE(count_of(e.out, "own", "max_ulps"), 1u) << e.out;  // its t: within one ulp of the exact t
  EXPECT_GT(count_of(e.out, "own", "crossings"), 500u) << e.out;
  EXPECT_EQ(count_of(e.out, "own", "hits"), count_of(e.out, "own", "crossings")) << e.out;
  EXPECT_NE(e.out.find("function 'own' answered all"), std::string::npos) << e.out;
}

TEST(CheckCrossingsCli, CrashHangUnreadableAndJson) {
  const auto mesh = write_file("cube.off", kCube);
  const auto r = run_rayproof(
      "check --crossings 'hang=sleep 30' --crossings 'junk=while read l; do echo 1 nope; done' "
      "--crossings 'crash=kill -SEGV $$' --mesh " + mesh.string() +
      " --crossings-rays 10 --crossings-sets random,invalid --crossings-timeout 0.2");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(count_of(r.out, "hang", "failures"), 10u) << r.out;
  EXPECT_EQ(count_of(r.out, "hang", "invalid_failures"), 8u) << r.out;
  EXPECT_EQ(count_of(r.out, "junk", "failures"), 10u) << r.out;
  EXPECT_NE(r.out.find("event: unreadable answer '1 nope'"), std::string::npos) << r.out;
  EXPECT_EQ(count_of(r.out, "crash", "failures"), 10u) << r.out;
  EXPECT_NE(r.out.find("event: crashed"), std::string::npos) << r.out;
  // Every ray answered "no hit": the crossings are missing, the invalid rays right.
  const auto j = run_rayproof("check --crossings 'none=while read l; do echo 0; done' --mesh " + mesh.string() +
                              " --crossings-rays 10 --crossings-sets random,invalid --json");
  ASSERT_EQ(j.status, 1) << j.err;
  const nlohmann::json out = nlohmann::json::parse(j.out);
  const nlohmann::json& run = out["functions"][0];
  EXPECT_EQ(run["rays"], 18);
  EXPECT_EQ(run["invalid_rays"], 8);
  EXPECT_EQ(run["hits"], 0);
  EXPECT_GT(run["crossings"].get<int>(), 0);
  EXPECT_EQ(run["missing"], run["crossings"]);
  EXPECT_EQ(run["findings"], run["crossings"]);
  EXPECT_EQ(run["sets"]["random"]["rays"], 10);
  EXPECT_TRUE(run["cost_ratio"].is_number()) << j.out;
}

// --out DIR: report.md holds the counts --json gives for a function answering no hit, beside
// rayproof's own exact crossings judged the same way with no finding; a DIR that cannot be made is
// refused.
TEST(CheckCrossingsCli, OutWritesTheReportBesideRayproofsOwn) {
  const auto mesh = write_file("cube.off", kCube);
  const auto dir = testing::scratch_dir() / "crossings_report";
  const std::string args = "check --crossings 'none=while read l; do echo 0; done' --mesh " + mesh.string() +
                           " --crossings-rays 10 --crossings-sets leak,random,invalid";
  const nlohmann::json run = testing::run_writing_report(args, dir);
  ASSERT_FALSE(run.empty());
  EXPECT_GT(run["missing"].get<int>(), 0);
  EXPECT_EQ(run["missing"], run["crossings"]);
  testing::expect_report_matches_json(dir, run, "none", mesh.string(), "rays",
                                      run["rays_with_findings"].get<std::uint64_t>(),
                                      {"rays", "crossings", "hits", "missing", "duplicates", "touch_hits", "no_contact",
                                       "garbage", "wrong_order", "t_over_tolerance", "max_ulps", "failures",
                                       "invalid_rays", "invalid_hit", "invalid_failures", "findings"});
  const auto own = testing::markdown_row(testing::slurp(dir / "report.md"), 0, "rayproof exact");
  ASSERT_FALSE(own.empty());
  EXPECT_EQ(own.at("hits"), own.at("crossings"));  // every crossing once
  EXPECT_EQ(own.at("crossings"), std::to_string(run["crossings"].get<int>()));
  testing::expect_unwritable_out_refused(args);
}

TEST(CheckCrossingsCli, BadUsageIsRefused) {
  const auto mesh = write_file("cube.off", kCube);
  EXPECT_EQ(run_rayproof("check --crossings 'x=cat'").status, 2);
  EXPECT_EQ(run_rayproof("check --crossings nocommand --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --crossings x=cat --distance y=cat --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --crossings x=cat --crossings-precision half --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --crossings x=cat --crossings-sets nope --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --crossings x=cat --crossings-timeout 0 --mesh " + mesh.string()).status, 2);
}

}  // namespace
}  // namespace rayproof
