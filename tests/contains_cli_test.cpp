// rayproof contains: the answers and tallies on a cube (inside known), JSON, segments, and the
// errors users meet (missing file, a bad points line, a NaN point, an open mesh with --rule nonzero)
// with clear messages; an open box answered by the generalized winding number.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
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
  r = run_rayproof("contains " + open.string() + " - --rule nonzero", "0 0 0\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("not closed: 3 edges are used by an odd number of triangles, e.g. vertex 0 (0, 0, 0) - vertex 1 (1, 0, 0)"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(r.out.empty());
}

TEST(ContainsCli, OpenMeshByTheGeneralizedWindingNumber) {
  // The cube without its top face (z = 2): the centre sees five faces, w = 5/6.
  std::string off = cube_off();
  off.replace(off.find("8 12 0"), 6, "8 10 0");
  off.erase(off.find("3 4 5 6\n3 5 7 6\n"), 16);
  const auto open = write_file("open_box.off", off);
  auto r = run_rayproof("contains " + open.string() + " - --winding", "1 1 1\n1 1 3\n0 0 0\n1 1 2\n");
  ASSERT_EQ(r.status, 0) << r.err;
  double w = 0, bound = 1;
  ASSERT_EQ(std::sscanf(r.out.c_str(), "inside %lf +- %lf", &w, &bound), 2) << r.out;
  EXPECT_LE(std::fabs(w - 5.0 / 6), bound) << r.out;
  ASSERT_EQ(std::sscanf(r.out.c_str() + r.out.find('\n') + 1, "outside %lf +- %lf", &w, &bound), 2) << r.out;
  EXPECT_LE(std::fabs(w - 1.0 / 6), bound) << r.out;  // (1 1 3) sees the opening: 4 atan(1 / sqrt 3) / 4 pi
  EXPECT_NE(r.out.find("\nsurface\noutside 0.5"), std::string::npos) << r.out;  // (1 1 2): w = 1/2 exactly, outside
  EXPECT_NE(r.err.find("4 points: 1 inside, 2 outside, 1 on the surface (rule winding: inside where the generalized "
                       "winding number > 1/2, the mesh is not closed, 10 triangles)"),
            std::string::npos)
      << r.err;
  r = run_rayproof("contains " + open.string() + " - --json --winding", "1 1 1\n");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"rule\": \"winding\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"winding\": [{\"w\": 0.83333333333333"), std::string::npos) << r.out;
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
