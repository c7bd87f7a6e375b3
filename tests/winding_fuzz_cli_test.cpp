// rayproof fuzz --winding: a short timed campaign with a fixed seed reports meshes and points and
// no finding (exit 0); --mesh --winding is the same mode; options of other modes are refused.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "cli_support.h"

namespace {

using rayproof::testing::run_rayproof;

TEST(WindingFuzzCli, TimedCampaignFindsNothing) {
  const auto r = run_rayproof("fuzz --winding --seconds 3 --seed 11");
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  const auto head = r.out.find("meshes     points  surface  near 1/2  bound misses  wrong side  wrong surface  errors");
  ASSERT_NE(head, std::string::npos) << r.out;
  std::istringstream row(r.out.substr(r.out.find('\n', head) + 1));
  unsigned long long meshes = 0, points = 0, surface = 0, near = 0, misses = 9, sides = 9, surfaces = 9, errors = 9;
  ASSERT_TRUE(row >> meshes >> points >> surface >> near >> misses >> sides >> surfaces >> errors) << r.out;
  EXPECT_GT(meshes, 10u);
  EXPECT_EQ(points, meshes * 28);
  EXPECT_GT(surface, 0u);
  EXPECT_LE(surface + near, points);
  EXPECT_EQ(misses + sides + surfaces + errors, 0u) << r.out;
  EXPECT_NE(r.out.find("meshes by kind: closed "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reproduce: rayproof fuzz --winding --seed 11 --cases " + std::to_string(meshes)), std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("finding:"), std::string::npos) << r.out;
}

TEST(WindingFuzzCli, MeshFlagAndRefusals) {
  auto r = run_rayproof("fuzz --mesh --winding --cases 6 --seed 3");
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("reproduce: rayproof fuzz --winding --seed 3 --cases 6"), std::string::npos) << r.out;
  r = run_rayproof("fuzz --winding --cases 2 --methods float");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--winding takes"), std::string::npos) << r.err;
  r = run_rayproof("fuzz --winding --distance --cases 2");
  EXPECT_EQ(r.status, 2);
}

}  // namespace
