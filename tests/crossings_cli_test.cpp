// rayproof cast MESH RAYS --query crossings [--touches]: one line per ray on a cube (through faces,
// a corner, grazing an edge, along a face, from inside), ranges, an open box, and the errors users
// meet (a bad ray line, a scene that is not a mesh file, --touches without crossings).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "cli_support.h"

namespace {

using rayproof::testing::run_rayproof;
using rayproof::testing::write_file;

/// [0, 2]^3 as an OFF file, outward; `faces` of its 12 triangles (the top face is the 3rd and 4th).
std::string cube_off(bool top = true) {
  return std::string("OFF\n8 ") + (top ? "12" : "10") +
         " 0\n0 0 0\n2 0 0\n0 2 0\n2 2 0\n0 0 2\n2 0 2\n0 2 2\n2 2 2\n3 0 2 1\n3 1 2 3\n" +
         (top ? "3 4 5 6\n3 5 7 6\n" : "") +
         "3 0 1 4\n3 1 5 4\n3 2 6 3\n3 3 6 7\n3 0 4 2\n3 2 4 6\n3 1 3 5\n3 3 7 5\n";
}

const char* kRays =
    "-1 0.5 0.75 1 0 0  # through two faces\n"
    "-1 -1 -1 1 1 1     # through two corners\n"
    "-1 1 1 1 0 1       # grazing the edge x = 0, z = 2\n"
    "-1 1 2 1 0 0       # along the top face\n"
    "1 1 1 1 0.25 0.5   # from inside\n"
    "1 1 1 0 0 0        # zero direction\n";

TEST(CrossingsCli, Lines) {
  const auto mesh = write_file("cube.off", cube_off());
  auto r = run_rayproof("cast " + mesh.string() + " - --query crossings", kRays);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "2 1.0:in 3.0:out\n2 1.0:in 3.0:out\n0\n0\n1 1.0:out\ninvalid\n");
  r = run_rayproof("cast " + mesh.string() + " - -q crossings --touches", kRays);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out,
            "2 1.0:in 3.0:out | 0\n2 1.0:in 3.0:out | 0\n0 | 1 1.0:edge\n"
            "0 | 4 1.0..2.0:coplanar 1.0:edge 2.0..3.0:coplanar 3.0:edge\n1 1.0:out | 0\ninvalid\n");
  r = run_rayproof("cast " + mesh.string() + " - -q crossings --tmin 2 --tmax 4", "-1 1 1 1 0 0\n");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "1 3.0:out\n");
}

TEST(CrossingsCli, OpenBox) {
  const auto mesh = write_file("open_box.off", cube_off(false));
  const auto r = run_rayproof("cast " + mesh.string() + " - --query crossings", "0.5 0.75 3 0 0 -1\n0.5 0.75 -1 0 0 1\n");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "1 3.0:out\n1 1.0:in\n");
}

TEST(CrossingsCli, ClearErrors) {
  const auto mesh = write_file("cube.off", cube_off());
  auto r = run_rayproof("cast " + mesh.string() + " - -q crossings", "-1 1 1 1 0 0\n1 2 3\n");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.out, "2 1.0:in 3.0:out\nerror\n");
  EXPECT_NE(r.err.find("-:2:"), std::string::npos) << r.err;
  r = run_rayproof("cast " + mesh.string() + " - --touches", "-1 1 1 1 0 0\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--touches goes with --query crossings"), std::string::npos) << r.err;
  r = run_rayproof("cast /nonexistent/m.off - -q crossings", "-1 1 1 1 0 0\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
  r = run_rayproof("cast " + mesh.string() + " - -q crossings --tmin 3 --tmax 1", "-1 1 1 1 0 0\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--tmin"), std::string::npos) << r.err;
}

}  // namespace

namespace {

// fuzz --mesh --crossings: a short campaign on the random closed meshes of fuzz --mesh passes, and
// says how many rays it aimed at vertices and edges (where all-hits double-counts).
TEST(CrossingsCli, FuzzCampaign) {
  auto r = rayproof::testing::run_rayproof("fuzz --mesh --crossings --cases 6 --seed 5");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("crossings: 6 meshes"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("aimed at a vertex or an edge midpoint"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("; 0 rays where the net count"), std::string::npos) << r.out;
  r = rayproof::testing::run_rayproof("fuzz --crossings --cases 1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--crossings goes with --mesh"), std::string::npos) << r.err;
}

}  // namespace

namespace {

// bench crossings on an octahedron: the rays through vertices are axis rays, each through one
// vertex where four triangles meet; Embree's counts (when built) are printed beside rayproof's.
std::string octahedron_off() {
  std::string s = "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n";
  for (int sx : {0, 1})
    for (int sy : {2, 3})
      for (int sz : {4, 5}) {
        const bool flip = ((sx == 1) + (sy == 3) + (sz == 5)) % 2;  // outward
        s += flip ? "3 " + std::to_string(sx) + " " + std::to_string(sz) + " " + std::to_string(sy) + "\n"
                  : "3 " + std::to_string(sx) + " " + std::to_string(sy) + " " + std::to_string(sz) + "\n";
      }
  return s;
}

TEST(CrossingsCli, BenchOnAnOctahedron) {
  const auto mesh = write_file("octahedron.off", octahedron_off());
  const auto r = run_rayproof("bench crossings " + mesh.string() + " --rays 300 --repeat 1");
  ASSERT_EQ(r.status, 0) << r.err;
  // A ray along the vertex's own axis crosses twice (in at one vertex, out at the opposite one);
  // along another axis it touches the vertex only: crossings / 2 + touches = rays.
  const std::string head = "rays through vertices: 300 rays; rayproof: ";
  const auto at = r.out.find(head);
  ASSERT_NE(at, std::string::npos) << r.out;
  std::size_t crossings = 0, touches = 0;
  ASSERT_EQ(std::sscanf(r.out.c_str() + at + head.size(), "%zu crossings, %zu touches", &crossings, &touches), 2) << r.out;
  EXPECT_EQ(crossings % 2, 0u);
  EXPECT_EQ(crossings / 2 + touches, 300u) << r.out;
  EXPECT_GT(crossings, 0u);
  EXPECT_GT(touches, 0u);
  EXPECT_NE(r.out.find("rayproof crossings"), std::string::npos) << r.out;
  if (r.out.find("embree all hits ") != std::string::npos) {
    EXPECT_NE(r.out.find("duplicates (a crossing reported again)"), std::string::npos) << r.out;
  }
}

}  // namespace
