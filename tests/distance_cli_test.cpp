// rayproof distance: the lines and JSON on a cube (distances, sides and tied triangles known by
// symmetry), --signed, clear errors (missing file, bad line, mesh without triangles), fuzz --distance.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
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

TEST(DistanceCli, LinesSignedAndJson) {
  const auto mesh = write_file("cube.off", cube_off());
  // The centre (1 from all twelve triangles: the first), above the top face's diagonal (triangles 2
  // and 3 tied), a vertex (on the surface), beyond vertex 7 (sqrt 3; triangles 3, 7, 11 share it).
  const std::string pts = "1 1 1\n1 1 3 # comment\n0 0 0\n3 3 3\n";
  auto r = run_rayproof("distance " + mesh.string() + " -", pts);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "1.0 inside 0\n1.0 outside 2\n0.0 surface 0\n1.7320508075688772 outside 3\n");
  EXPECT_NE(r.err.find("4 points: 1 inside, 2 outside, 1 on the surface (12 triangles)"), std::string::npos) << r.err;
  r = run_rayproof("distance " + mesh.string() + " - --signed", pts);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "-1.0 1.0 inside 0\n1.0 1.0 outside 2\n0.0 0.0 surface 0\n1.7320508075688772 1.7320508075688772 outside 3\n");
  r = run_rayproof("distance " + mesh.string() + " - --json --signed", "3 3 3\n1 1 -0.5\n");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("{\"distance\": 1.7320508075688772, \"signed\": 1.7320508075688772, \"side\": \"outside\", "
                       "\"triangle\": 3, \"point\": [2.0, 2.0, 2.0]"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("{\"distance\": 0.5, \"signed\": 0.5, \"side\": \"outside\", \"triangle\": 0, \"point\": [1.0, 1.0, 0.0]"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("\"count\": 2, \"inside\": 0, \"outside\": 2, \"surface\": 0}"), std::string::npos) << r.out;
  // A distance beyond double's range is inf, which JSON has no number for: written as the string "inf"
  // (the whole output must parse as JSON).
  r = run_rayproof("distance " + mesh.string() + " - --json --signed", "1.5e308 1.5e308 1.5e308\n");
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json doc = nlohmann::json::parse(r.out, nullptr, false);
  ASSERT_FALSE(doc.is_discarded()) << r.out;
  EXPECT_EQ(doc["points"][0]["distance"], "inf") << r.out;
  EXPECT_EQ(doc["points"][0]["signed"], "inf") << r.out;
  EXPECT_EQ(doc["points"][0]["point"][0], 2.0) << r.out;
}

TEST(DistanceCli, ClearErrors) {
  const auto mesh = write_file("cube.off", cube_off());
  auto r = run_rayproof("distance /nonexistent/m.off -", "1 1 1\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
  r = run_rayproof("distance " + mesh.string() + " -", "1 1 1\n1 2\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("-:2: 2 numbers, expected 3 (x y z)"), std::string::npos) << r.err;
  r = run_rayproof("distance " + mesh.string() + " -", "1 nan 1\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("-:1: coordinate 2 is NaN or infinite"), std::string::npos) << r.err;
  const auto empty = write_file("empty.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  r = run_rayproof("distance " + empty.string() + " -", "1 1 1\n");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no triangles"), std::string::npos) << r.err;
}

TEST(DistanceCli, FuzzDistance) {
  // A short campaign: counts printed, no finding, exit 0; wrong options refused.
  auto r = run_rayproof("fuzz --distance --cases 40 --seed 2");
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("wrong triangle  wrong distance  wrong side"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("      40      960               0               0           0"), std::string::npos) << r.out;
  r = run_rayproof("fuzz --distance --cases 2 --methods float");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--distance takes"), std::string::npos) << r.err;
}

TEST(DistanceCli, BenchDistanceOnACube) {
  // The table per point set, rayproof with no wrong triangle and no distance off, the stage tally.
  const auto mesh = write_file("cube.off", cube_off());
  const auto r = run_rayproof("bench distance " + mesh.string() + " --points 300 --repeat 1");
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("uniform in the box grown by 20%: 300 points"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("near the surface (within 1e-3 of the diagonal): 300 points"), std::string::npos) << r.out;
  const auto row = r.out.find("  rayproof   ");
  ASSERT_NE(row, std::string::npos) << r.out;
  const std::string line = r.out.substr(row, r.out.find('\n', row) - row);
  EXPECT_NE(line.find("1.00x         0          0         0"), std::string::npos) << line;
  EXPECT_NE(r.out.find("reference check on 300 points: 0 differ"), std::string::npos) << r.out;
  EXPECT_EQ(run_rayproof("bench distance " + mesh.string() + " --points 0").status, 2);
}

}  // namespace
