// rayproof contains: the answers and tallies on a cube (inside known), JSON, segments, and the
// errors users meet (missing file, a bad points line, a NaN point, an open mesh) with clear messages.
#include <gtest/gtest.h>

#include <string>

#include "cli_support.h"

namespace {

using rayproof::testing::run_rayproof;
using rayproof::testing::write_file;

/// [0, 2]^3 as an OFF file, outward.
std::string cube_off() {
  return "OFF\n8 12 0\n0 0 0\n2 0 0\n0 2 0\n2 2 0\n0 0 2\n2 0 2\n0 2 2\n2 2 2\n"
         "3 0 2 1\n3 1 2 3\n3 4 5 6\n3 5 7 6\n3 0 1 4\n3 1 5 4\n3 2 6 3\n3 3 6 7\n3 0 4 2\n3 2 4 6\n3 1 3 5\n3 3 7 5\n";
}

TEST(ContainsCli, SidesAndTallies) {
  const auto mesh = write_file("cube.off", cube_off());
  // Inside, on a face diagonal's ray, on a vertex, on an edge, outside, one ulp outside.
  const auto r = run_rayproof("contains " + mesh.string() + " -",
                              "1 1 1\n1 0.5 1.5 # comment\n0 0 0\n1 0 0\n3 1 1\n\n0x1.0000000000001p+1 1 1\n");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "inside\ninside\nsurface\nsurface\noutside\noutside\n");
  EXPECT_NE(r.err.find("6 points: 2 inside, 2 outside, 2 on the surface (rule nonzero, 12 triangles)"), std::string::npos) << r.err;
  const auto j = run_rayproof("contains " + mesh.string() + " - --json --winding", "1 1 1\n2 1 1\n5 5 5\n");
  ASSERT_EQ(j.status, 0) << j.err;
  EXPECT_NE(j.out.find("\"points\": [\"inside\", \"surface\", \"outside\"], \"winding\": [1, null, 0], \"count\": 3, "
                       "\"inside\": 1, \"outside\": 1, \"surface\": 1}"),
            std::string::npos)
      << j.out;
}

TEST(ContainsCli, Segments) {
  const auto mesh = write_file("cube.off", cube_off());
  const auto r = run_rayproof("contains " + mesh.string() + " - --segments", "-1 1 1 1 1 1\n0.5 0.5 0.5 1 1 1\n");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "edge 0.5 8 outside inside\nmiss - - inside inside\n");
  EXPECT_NE(r.err.find("2 segments: 1 meet the surface, 1 do not"), std::string::npos) << r.err;
}

TEST(ContainsCli, ClearErrors) {
  const auto mesh = write_file("cube.off", cube_off());
  auto r = run_rayproof("contains /nonexistent/m.off -", "1 1 1\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
  r = run_rayproof("contains " + mesh.string() + " /nonexistent/points.txt");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("/nonexistent/points.txt: no such file"), std::string::npos) << r.err;
  r = run_rayproof("contains " + mesh.string() + " -", "1 1 1\n1 2\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("-:2: 2 numbers, expected 3 (x y z)"), std::string::npos) << r.err;
  r = run_rayproof("contains " + mesh.string() + " -", "1 one 1\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("-:1: 'one 1' is not a number"), std::string::npos) << r.err;
  r = run_rayproof("contains " + mesh.string() + " -", "1 1 1\n\n1 nan 1\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("-:3: coordinate 2 is NaN or infinite"), std::string::npos) << r.err;
  const auto open = write_file("open.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  r = run_rayproof("contains " + open.string() + " -", "0 0 0\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("not closed: 3 edges are used by an odd number of triangles, e.g. vertex 0 (0, 0, 0) - vertex 1 (1, 0, 0)"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(r.out.empty());
}

}  // namespace

namespace {

TEST(ContainsCli, BenchContainsTalliesAndVerdicts) {
  // A small run: the cube as a mesh (Epick and Embree beside contains, no Epeck: no reference for
  // the mesh's own sets), then the three shapes against their closed forms.
  const auto mesh = write_file("cube.off", cube_off());
  const auto r = run_rayproof("bench contains " + mesh.string() + " --points 300 --hard-vertices 4 --repeat 1 --no-epeck");
  ASSERT_EQ(r.status, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("cube random: 300 points, 0 of them on the surface (reference: none;"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cube hard: 40 points"), std::string::npos) << r.out;  // 10 per sampled vertex
  EXPECT_NE(r.out.find("cube lattice+ulp: 24853 points, 7682 of them on the surface (reference: closed form;"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("contains: 0 wrong answers over every point set with a reference (target 0): met"), std::string::npos) << r.out;
}

}  // namespace
