// rayproof check --contains: programs speaking the containment line protocol, judged on a mesh
// file. The example parity test is caught on the surface sets and its NaN crash reported; the
// example wrapping `rayproof contains` has no finding; hangs and garbage are reported and the run
// goes on.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "cli_support.h"
#include "judge_report_support.h"

namespace rayproof {
namespace {

using testing::run_rayproof;
using testing::write_file;

const std::string& kCube = testing::kUnitCubeOff;

std::string example(const char* name) { return std::string(RAYPROOF_DATA_DIR) + "/../examples/contains/" + name; }

using testing::have_numpy;

/// The value of `key` in the summary of function `fn` (the first mesh it ran on).
std::size_t count_of(const std::string& out, const std::string& fn, const std::string& key) {
  return testing::summary_count(out, "function '" + fn + "'", key);
}

TEST(CheckContainsCli, ExampleParityIsCaughtAndTheNanCrashIsReported) {
  if (!have_numpy()) GTEST_SKIP() << "/usr/bin/python3 has no numpy";
  const auto mesh = write_file("cube.off", kCube);
  const auto r = run_rayproof("check --contains 'parity=/usr/bin/python3 " + example("parity_contains.py") +
                              " --crash-on-nan' --mesh " + mesh.string() + " --contains-points 100");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_GT(count_of(r.out, "parity", "outside_called_inside") + count_of(r.out, "parity", "inside_called_outside"),
            0u)
      << r.out;
  EXPECT_EQ(count_of(r.out, "parity", "invalid_failures"), 5u) << r.out;  // one crash per point with a NaN
  EXPECT_EQ(count_of(r.out, "parity", "failures"), 0u) << r.out;
  EXPECT_EQ(count_of(r.out, "parity", "surface"), count_of(r.out, "parity", "surface_said_outside") +
                                                      count_of(r.out, "parity", "surface_said_inside"))
      << r.out;
  EXPECT_NE(r.out.find("set random   points     100  findings       0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("set=nudged mesh=" + mesh.string() + " point "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("event: crashed (signal 11"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("function 'parity' differs from exact on"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cost: judging"), std::string::npos) << r.out;
}

TEST(CheckContainsCli, ExampleWrappingRayproofContainsHasNoFinding) {
  const auto mesh = write_file("cube.off", kCube);
  const auto r = run_rayproof("check --contains 'exact=/usr/bin/python3 " + example("rayproof_contains.py") + " " +
                              RAYPROOF_BIN + "' --mesh " + mesh.string() + " --contains-points 100");
  EXPECT_EQ(r.status, 0) << r.err << r.out;
  EXPECT_EQ(count_of(r.out, "exact", "findings"), 0u) << r.out;
  EXPECT_EQ(count_of(r.out, "exact", "surface_said_surface"), count_of(r.out, "exact", "surface")) << r.out;
  EXPECT_NE(r.out.find("function 'exact' answered all"), std::string::npos) << r.out;
  const auto f = run_rayproof("check --contains 'exact=/usr/bin/python3 " + example("rayproof_contains.py") + " " +
                              RAYPROOF_BIN + "' --mesh " + mesh.string() +
                              " --contains-points 100 --contains-precision float --contains-sets nudged,random");
  EXPECT_EQ(f.status, 0) << f.err << f.out;
  EXPECT_NE(f.out.find("rule automatic, float precision"), std::string::npos) << f.out;
}

// --contains-scale: the cube times 2^600 and 2^-600, exactly: rayproof's own contains has no finding
// and every set is as large as at scale 1; scales that are not powers of two or would not be exact
// are refused.
TEST(CheckContainsCli, ExtremeScalesAreJudgedExactly) {
  const auto mesh = write_file("cube.off", kCube);
  const std::string exact = "'exact=/usr/bin/python3 " + example("rayproof_contains.py") + " " + RAYPROOF_BIN + "'";
  const auto judged = [&](const std::string& scale) {
    const auto r = run_rayproof("check --contains " + exact + " --mesh " + mesh.string() +
                                " --contains-points 100 --contains-max-per-set 100 --json --contains-scale " + scale);
    EXPECT_EQ(r.status, 0) << scale << r.err << r.out;
    return nlohmann::json::parse(r.out)["functions"][0];
  };
  const nlohmann::json one = judged("1");
  for (const char* scale : {"2^600", "2^-600"}) {
    const nlohmann::json run = judged(scale);
    EXPECT_EQ(run["findings"], 0) << scale;
    for (const char* key : {"points", "inside", "surface", "invalid_points"}) EXPECT_EQ(run[key], one[key]) << scale << key;
    ASSERT_EQ(run["sets"].size(), one["sets"].size()) << scale;
    for (const auto& [set, counts] : one["sets"].items()) EXPECT_EQ(run["sets"][set]["points"], counts["points"]) << scale << " " << set;
  }
  EXPECT_EQ(run_rayproof("check --contains x=cat --mesh " + mesh.string() + " --contains-scale 10").status, 2);
  EXPECT_EQ(run_rayproof("check --contains x=cat --mesh " + mesh.string() + " --contains-scale 2^1100").status, 2);
  const auto r = run_rayproof("check --contains x=cat --mesh " + mesh.string() + " --contains-scale 2^-1050");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("falls below double's range of normal numbers"), std::string::npos) << r.err;
}

TEST(CheckContainsCli, HangAndGarbageAreReportedAndTheRunGoesOn) {
  const auto mesh = write_file("cube.off", kCube);
  const auto r = run_rayproof("check --contains 'hang=sleep 30' --contains 'junk=while read l; do echo hello; done' "
                              "--contains 'seven=while read l; do echo 7; done' --mesh " + mesh.string() +
                              " --contains-points 10 --contains-sets random,invalid --contains-timeout 0.2");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(count_of(r.out, "hang", "failures"), 10u) << r.out;
  EXPECT_EQ(count_of(r.out, "hang", "invalid_failures"), 10u) << r.out;
  EXPECT_NE(r.out.find("event: timed out: no answer for 0.2 s on points 0..9 (set random; 10 points"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(count_of(r.out, "junk", "failures"), 10u) << r.out;
  EXPECT_NE(r.out.find("event: unreadable answer 'hello'"), std::string::npos) << r.out;
  EXPECT_EQ(count_of(r.out, "seven", "garbage"), 20u) << r.out;
  EXPECT_EQ(count_of(r.out, "seven", "findings"), 20u) << r.out;
  EXPECT_NE(r.out.find("garbage set=random mesh="), std::string::npos) << r.out;
}

// A program that answers each point as it reads it, on a batch whose answers overflow a pipe: its
// answers are read while the batch is written (else both sides wait on full pipes until the timeout).
TEST(CheckContainsCli, AProgramAnsweringAsItReadsALargeBatchDoesNotDeadlock) {
  const auto mesh = write_file("cube.off", kCube);
  const auto script = write_file("stream.py", R"(import sys
n = 0
for line in iter(sys.stdin.readline, ""):
    if line.startswith("points"):
        n = int(line.split()[1])
    elif n > 0:
        print(0, flush=True)
        n -= 1
)");
  const auto r = run_rayproof("check --contains 'stream=/usr/bin/python3 " + script.string() + "' --mesh " +
                              mesh.string() +
                              " --contains-points 60000 --contains-max-per-set 60000 --contains-sets random "
                              "--contains-batch 60000 --contains-timeout 5");
  EXPECT_EQ(count_of(r.out, "stream", "points"), 60000u) << r.out << r.err;
  EXPECT_EQ(count_of(r.out, "stream", "failures"), 0u) << r.out;
  EXPECT_EQ(count_of(r.out, "stream", "outside_called_inside"), 0u) << r.out;
  EXPECT_EQ(r.out.find("event:"), std::string::npos) << r.out;
}

// --json holds the counts the text prints, under the same keys.
TEST(CheckContainsCli, JsonHoldsTheCountsOfTheText) {
  if (!have_numpy()) GTEST_SKIP() << "/usr/bin/python3 has no numpy";
  const auto mesh = write_file("cube.off", kCube);
  const std::string args = "check --contains 'p=/usr/bin/python3 " + example("parity_contains.py") + "' --mesh " +
                           mesh.string() + " --contains-points 50 --contains-sets vertex,nudged,random,invalid";
  const auto text = run_rayproof(args);
  const auto json = run_rayproof(args + " --json");
  EXPECT_EQ(text.status, 1) << text.err;
  ASSERT_EQ(json.status, 1) << json.err;
  const nlohmann::json out = nlohmann::json::parse(json.out);
  ASSERT_EQ(out["functions"].size(), 1u) << json.out;
  const nlohmann::json& run = out["functions"][0];
  for (const char* key : {"points", "inside", "surface", "inside_called_outside", "outside_called_inside",
                          "false_surface", "surface_said_outside", "surface_said_inside", "surface_said_surface",
                          "rules_differ", "rules_differ_other", "winding_near_half", "garbage", "failures",
                          "invalid_points", "invalid_said_inside", "invalid_said_surface", "invalid_failures",
                          "findings"}) {
    ASSERT_TRUE(run.contains(key)) << key << "\n" << json.out;
    EXPECT_EQ(run[key].get<std::size_t>(), count_of(text.out, "p", key)) << key << "\n" << text.out;
  }
  EXPECT_EQ(run["rule"], "nonzero");
  EXPECT_EQ(run["sets"]["random"]["points"], 50);
  EXPECT_TRUE(run["cost_ratio"].is_number()) << json.out;
  EXPECT_TRUE(out["findings"].get<bool>());
}

// Debian's Open3D 0.16 (python3-open3d) under Debian's Embree 3: compute_occupancy calls every
// point outside (its rays carry a mask Debian's Embree does not enable: they miss everything), and
// Embree's assertion on a ray from a point beyond 1.8e19 aborts the process. Judged through the
// example; the counts are Open3D's, so this test fails the day Open3D answers differently.
TEST(CheckContainsCli, DebianOpen3dCallsEveryPointOutsideAndItsAbortsAreReported) {
  if (std::system("/usr/bin/python3 -c 'import open3d' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 has no open3d (Debian: python3-open3d)";
  const auto mesh = write_file("cube.off", kCube);
  const auto r = run_rayproof("check --contains 'o3d=/usr/bin/python3 " + example("open3d_contains.py") +
                              "' --contains-precision float --mesh " + mesh.string() +
                              " --contains-points 200 --contains-sets random,far");
  EXPECT_EQ(r.status, 1) << r.err;
  const std::size_t inside = count_of(r.out, "o3d", "inside");
  EXPECT_GT(inside, 100u) << r.out;
  EXPECT_EQ(count_of(r.out, "o3d", "inside_called_outside"), inside) << r.out;
  EXPECT_EQ(count_of(r.out, "o3d", "outside_called_inside"), 0u) << r.out;
  EXPECT_GT(count_of(r.out, "o3d", "failures"), 0u) << r.out;
  EXPECT_NE(r.out.find("event: crashed (signal 6"), std::string::npos) << r.out;
}

// --out DIR: report.md holds the counts --json gives for a function calling every point outside,
// beside rayproof's own exact contains judged the same way with no finding; a DIR that cannot be
// made is refused.
TEST(CheckContainsCli, OutWritesTheReportBesideRayproofsOwn) {
  const auto mesh = write_file("cube.off", kCube);
  const auto dir = testing::scratch_dir() / "contains_report";
  const std::string args = "check --contains 'out=while read l; do echo 0; done' --mesh " + mesh.string() +
                           " --contains-points 20 --contains-sets vertex,nudged,random,invalid";
  const nlohmann::json run = testing::run_writing_report(args, dir);
  ASSERT_FALSE(run.empty());
  EXPECT_GT(run["inside_called_outside"].get<int>(), 0);
  EXPECT_EQ(run["inside_called_outside"], run["inside"]);
  testing::expect_report_matches_json(dir, run, "out", mesh.string(), "points", run["findings"].get<std::uint64_t>(),
                                      {"points", "inside", "surface", "inside_called_outside", "outside_called_inside",
                                       "false_surface", "surface_said_outside", "rules_differ", "garbage", "failures",
                                       "invalid_points", "invalid_failures", "findings"});
  const auto own = testing::markdown_row(testing::slurp(dir / "report.md"), 0, "rayproof exact");
  ASSERT_FALSE(own.empty());
  EXPECT_EQ(own.at("surface_said_surface"), own.at("surface"));  // rayproof answers 2 on the surface
  testing::expect_unwritable_out_refused(args);
}

TEST(CheckContainsCli, BadUsageIsRefused) {
  const auto mesh = write_file("cube.off", kCube);
  const auto open = write_file("open.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(run_rayproof("check --contains 'x=cat'").status, 2);
  EXPECT_EQ(run_rayproof("check --contains nocommand --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --contains x=cat --caster y=cat --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --contains x=cat --contains-rule majority --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --contains x=cat --contains-sets nope --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --contains x=cat --contains-timeout 0 --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --contains x=cat --contains-precision half --mesh " + mesh.string()).status, 2);
  const auto nonzero = run_rayproof("check --contains x=cat --contains-rule nonzero --mesh " + open.string());
  EXPECT_EQ(nonzero.status, 2);
  EXPECT_NE(nonzero.err.find("not closed"), std::string::npos) << nonzero.err;
}

}  // namespace
}  // namespace rayproof
