// rayproof check --distance: programs speaking the distance line protocol, judged on a mesh file.
// The numpy example is caught (far points overflow to inf, a subnormal distance rounds to 0); the
// example wrapping `rayproof distance` has no finding, signed or not; hangs and unreadable answers
// are reported and the run goes on.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "cli_support.h"

namespace rayproof {
namespace {

using testing::run_rayproof;
using testing::write_file;

const std::string& kCube = testing::kUnitCubeOff;

std::string example(const char* name) { return std::string(RAYPROOF_DATA_DIR) + "/../examples/distance/" + name; }

using testing::have_numpy;

/// The value of `key` in the summary of function `fn` (the first mesh it ran on).
std::size_t count_of(const std::string& out, const std::string& fn, const std::string& key) {
  return testing::summary_count(out, "function '" + fn + "'", key);
}

TEST(CheckDistanceCli, NumpyExampleIsCaughtAndRayproofsOwnIsNot) {
  if (!have_numpy()) GTEST_SKIP() << "/usr/bin/python3 has no numpy";
  const auto mesh = write_file("cube.off", kCube);
  const auto r = run_rayproof("check --distance 'np=/usr/bin/python3 " + example("numpy_distance.py") + "' --mesh " +
                              mesh.string() + " --distance-points 100");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_GT(count_of(r.out, "np", "over_tolerance"), 0u) << r.out;
  EXPECT_EQ(count_of(r.out, "np", "invalid_number"), 0u) << r.out;
  EXPECT_NE(r.out.find("over-tolerance set=far mesh=" + mesh.string() + " point "), std::string::npos) << r.out;
  for (const char* sign : {"", " --signed"}) {
    const auto e = run_rayproof("check --distance 'exact=/usr/bin/python3 " + example("rayproof_distance.py") + " " +
                                RAYPROOF_BIN + sign + "' --mesh " + mesh.string() + " --distance-points 100" +
                                (*sign ? " --distance-signed" : ""));
    EXPECT_EQ(e.status, 0) << sign << e.err << e.out;
    EXPECT_EQ(count_of(e.out, "exact", "max_ulps"), 0u) << e.out;
    EXPECT_NE(e.out.find("function 'exact' answered all"), std::string::npos) << e.out;
  }
}

TEST(CheckDistanceCli, HangUnreadableAndJson) {
  const auto mesh = write_file("cube.off", kCube);
  const auto r = run_rayproof("check --distance 'hang=sleep 30' --distance 'junk=while read l; do echo hello; done' "
                              "--mesh " + mesh.string() +
                              " --distance-points 10 --distance-sets random,invalid --distance-timeout 0.2");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(count_of(r.out, "hang", "failures"), 10u) << r.out;
  EXPECT_EQ(count_of(r.out, "hang", "invalid_failures"), 10u) << r.out;
  EXPECT_EQ(count_of(r.out, "junk", "failures"), 10u) << r.out;
  EXPECT_NE(r.out.find("event: unreadable answer 'hello'"), std::string::npos) << r.out;
  const auto j = run_rayproof("check --distance 'zero=while read l; do echo 0; done' --mesh " + mesh.string() +
                              " --distance-points 10 --distance-sets random --json");
  ASSERT_EQ(j.status, 1) << j.err;
  const nlohmann::json out = nlohmann::json::parse(j.out);
  const nlohmann::json& run = out["functions"][0];
  EXPECT_EQ(run["points"], 10);
  EXPECT_EQ(run["over_tolerance"], 10);
  EXPECT_EQ(run["signed"], false);
  EXPECT_TRUE(run["cost_ratio"].is_number()) << j.out;
}

TEST(CheckDistanceCli, BadUsageIsRefused) {
  const auto mesh = write_file("cube.off", kCube);
  EXPECT_EQ(run_rayproof("check --distance 'x=cat'").status, 2);
  EXPECT_EQ(run_rayproof("check --distance nocommand --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --distance x=cat --contains y=cat --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --distance x=cat --distance-rel-tol -1 --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --distance x=cat --distance-sets nope --mesh " + mesh.string()).status, 2);
}

}  // namespace
}  // namespace rayproof
