// rayproof intersect: pairs of one mesh and of two, --count, --json, --classes, and the errors users
// meet (a missing file, a mesh without triangles, a NaN vertex) with clear messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "cli_support.h"

namespace {

using rayproof::testing::run_rayproof;
using rayproof::testing::write_file;

/// The box [x, x + 2] x [0, 2]^2 as OFF faces over vertices numbered from `first`.
std::string box_off(double x) {
  std::string s;
  for (int i = 0; i < 8; ++i)
    s += std::to_string(x + 2 * (i & 1)) + " " + std::to_string(2 * (i >> 1 & 1)) + " " + std::to_string(2 * (i >> 2 & 1)) + "\n";
  return s;
}
std::string faces(int first) {
  const int t[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                        {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  std::string s;
  for (const auto& f : t)
    s += "3 " + std::to_string(f[0] + first) + " " + std::to_string(f[1] + first) + " " + std::to_string(f[2] + first) + "\n";
  return s;
}

TEST(IntersectCli, OneMeshAndTwo) {
  const auto cube = write_file("cube.off", "OFF\n8 12 0\n" + box_off(0) + faces(0));
  auto r = run_rayproof("intersect " + cube.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find("0 pairs (0 of them a zero-area triangle alone) among 12 triangles"), std::string::npos) << r.err;
  // Two boxes touching at x = 2 under other indices: the faces there overlap.
  const auto both = write_file("two.off", "OFF\n16 24 0\n" + box_off(0) + box_off(2) + faces(0) + faces(8));
  r = run_rayproof("intersect " + both.string() + " --threads 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("10 20\n10 21\n"), std::string::npos) << r.out;
  const auto count = run_rayproof("intersect " + both.string() + " --count");
  ASSERT_EQ(count.status, 0) << count.err;
  const auto lines = std::count(r.out.begin(), r.out.end(), '\n');
  EXPECT_EQ(count.out, std::to_string(lines) + "\n");
  // The two boxes as two meshes: the same pairs, the second's triangles numbered from 0.
  const auto right = write_file("right.off", "OFF\n8 12 0\n" + box_off(2) + faces(0));
  r = run_rayproof("intersect " + cube.string() + " " + right.string() + " --json --classes");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("[10, 8, \"coplanar_overlap\"], [10, 9, \"coplanar_touching\"]"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"count\": " + std::to_string(lines) + "}"), std::string::npos) << r.out;
}

TEST(IntersectCli, ClearErrors) {
  auto r = run_rayproof("intersect /nonexistent/m.off");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
  const auto empty = write_file("empty.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  r = run_rayproof("intersect " + empty.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("the mesh has no triangles"), std::string::npos) << r.err;
  const auto nan = write_file("nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n");
  r = run_rayproof("intersect " + nan.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("nan.off:4: vertex x is not finite"), std::string::npos) << r.err;
}

}  // namespace
