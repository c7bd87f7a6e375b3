// rayproof fuzz --winding: a short timed campaign with a fixed seed reports meshes and points and
// no finding (exit 0); --mesh --winding is the same mode; options of other modes are refused.
// rayproof bench contains --open: an open mesh beside its closed original, the ablation rows.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "cli_support.h"

namespace {

using rayproof::testing::run_rayproof;
using rayproof::testing::write_file;

/// An octahedron, outward; `skip` faces left out (an open one).
std::string octahedron_off(int skip) {
  std::string s = "OFF\n6 " + std::to_string(8 - skip) + " 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n";
  const char* faces[8] = {"0 2 4", "2 1 4", "1 3 4", "3 0 4", "2 0 5", "1 2 5", "3 1 5", "0 3 5"};
  for (int f = skip; f < 8; ++f) s += std::string("3 ") + faces[f] + "\n";
  return s;
}

TEST(WindingBenchCli, OpenMeshBesideItsClosedOriginal) {
  // octa-with-holes.off is paired with the octa.off beside it; 3000 points: the two-thread batch runs.
  const auto closed = write_file("octa.off", octahedron_off(0));
  const auto open = write_file("octa-with-holes.off", octahedron_off(1));
  const auto r = run_rayproof("bench contains " + closed.string() + " --open " + open.string() +
                              " --points 3000 --repeat 1 --no-epeck --threads 2");
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("octa-with-holes (7 triangles, not closed): 3000 random points in its box"), std::string::npos) << r.out;
  for (const char* row : {"contains on the closed octa ", "  without the near bound ", "  caps as "})
    EXPECT_NE(r.out.find(row), std::string::npos) << row << "\n" << r.out;
  EXPECT_EQ(r.out.find("answers differ from the default build"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("contains against the brute force where |w - 1/2| >= 1e-6: 0 wrong of 3000"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("octa-with-holes: winding contains / contains on the closed octa, one thread = "), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("octa-with-holes: winding contains, 2 threads / one = "), std::string::npos) << r.out;
  // OPEN=CLOSED names the original; fewer than 2048 points: the thread rows are skipped, and said so.
  const auto r2 = run_rayproof("bench contains " + closed.string() + " --open " + open.string() + "=" + closed.string() +
                               " --points 500 --repeat 1 --no-epeck");
  ASSERT_EQ(r2.status, 0) << r2.out << r2.err;
  EXPECT_NE(r2.out.find("contains on the closed octa "), std::string::npos) << r2.out;
  EXPECT_NE(r2.out.find("2 threads not timed: below 2048 points the batch runs on one thread"), std::string::npos) << r2.out;
}

TEST(WindingFuzzCli, TimedCampaignFindsNothing) {
  const auto r = run_rayproof("fuzz --winding --seconds 3 --seed 11");
  ASSERT_EQ(r.status, 0) << r.out << r.err;
  const auto head = r.out.find("meshes     points  surface  near 1/2  bound misses  wrong side  wrong surface  errors");
  ASSERT_NE(head, std::string::npos) << r.out;
  std::istringstream row(r.out.substr(r.out.find('\n', head) + 1));
  unsigned long long meshes = 0, points = 0, surface = 0, near = 0, misses = 9, sides = 9, surfaces = 9, errors = 9;
  ASSERT_TRUE(row >> meshes >> points >> surface >> near >> misses >> sides >> surfaces >> errors) << r.out;
  // Every fourth open mesh also tabulates the caps' field over a batch of 4096 points: under the
  // sanitizers 3 s hold about 8 meshes (more than 100 in a Release build).
  EXPECT_GE(meshes, 4u);
  EXPECT_EQ(points, meshes * 28);
  EXPECT_NE(r.out.find(" points, 0 sides that differ from the point asked alone\n"), std::string::npos) << r.out;
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
