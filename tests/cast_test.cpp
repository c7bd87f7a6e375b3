// rayproof cast and render as a user runs them: outputs, classes, messages and exit statuses.
#include <gtest/gtest.h>

#include "cli_support.h"

using rayproof::testing::run_rayproof;
using rayproof::testing::write_file;

namespace {
// Two unit squares (z = 0 and z = 2), each as two triangles sharing the diagonal (0,0)-(1,1).
const char* kSquares = "OFF\n8 4 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 2\n1 0 2\n1 1 2\n0 1 2\n"
                       "3 0 1 2\n3 0 2 3\n3 4 5 6\n3 4 6 7\n";
}  // namespace

TEST(Cast, ClosestAnyAllOnAMesh) {
  const auto mesh = write_file("sq.off", kSquares);
  const auto rays = write_file("rays.txt",
                               "# interior, diagonal edge, vertex, miss, tmin past the first square\n"
                               "0.25 0.5 -1 0 0 1\n0.5 0.5 -1 0 0 1\n1 1 -1 0 0 1\n5 5 -1 0 0 1\n0 0 0 0 0 0\n");
  auto r = run_rayproof("cast " + mesh.string() + " " + rays.string() + " --method exact");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "interior 1.0 1\nedge 1.0 0\nvertex 1.0 0\nmiss - -\ninvalid - -\n");
  r = run_rayproof("cast " + mesh.string() + " " + rays.string() + " --query any");
  EXPECT_EQ(r.out, "hit\nhit\nhit\nmiss\ninvalid - -\n");
  r = run_rayproof("cast " + mesh.string() + " " + rays.string() + " --query all --method watertight");
  EXPECT_EQ(r.out, "interior 1.0 1 interior 3.0 3\nedge 1.0 0 edge 1.0 1 edge 3.0 2 edge 3.0 3\n"
                   "vertex 1.0 0 vertex 1.0 1 vertex 3.0 2 vertex 3.0 3\nmiss - -\ninvalid - -\n");
  r = run_rayproof("cast " + mesh.string() + " - --tmin 1.5", "0.25 0.5 -1 0 0 1\n");
  EXPECT_EQ(r.out, "interior 3.0 3\n");
}

TEST(Cast, ErrorsAreNamed) {
  const auto mesh = write_file("sq2.off", kSquares);
  auto r = run_rayproof("cast " + mesh.string() + " -", "0 0 -1 0 0 1\n1 2 x 0 0 1\n");
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.out, "vertex 1.0 0\nerror - -\n");
  EXPECT_NE(r.err.find("-:2: 'x' is not a number"), std::string::npos) << r.err;
  const auto bad = write_file("bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n");
  r = run_rayproof("cast " + bad.string() + " -", "0 0 -1 0 0 1\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("bad.off:6: vertex index 9 out of range (3 vertices)"), std::string::npos) << r.err;
  r = run_rayproof("cast " + mesh.string() + " - --method nope", "");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown method 'nope'"), std::string::npos) << r.err;
}

TEST(Render, DefaultSceneVerifiesCleanForWatertight) {
  const auto out = rayproof::testing::scratch_dir() / "img.png";
  const auto r = run_rayproof("render default --out " + out.string() + " --width 64 --height 48 --method watertight --verify");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("false_miss 0 false_hit 0 wrong_feature 0 (of 3072 pixels"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(out));
}
