// rayproof bench intersect: the sentences built from known tallies, the generated meshes' known
// contacts, the Open3D scope (pairs sharing no vertex index), a tiny mesh end to end through the
// command, and clear errors for a missing file, a mesh that does not load and a NaN vertex.
#include <gtest/gtest.h>

#include <string>

#include "cli_support.h"
#include "scene/compare/intersect_bench.h"

namespace {

namespace cmp = rayproof::scene::compare;
using rayproof::testing::run_rayproof;
using rayproof::testing::write_file;

cmp::IntersectRow row_of(std::size_t pairs, double seconds) {
  cmp::IntersectRow r;
  r.name = "m";
  r.triangles = 100;
  r.pairs = pairs;
  r.seconds = seconds;
  return r;
}

cmp::PeerRow peer(const char* name, std::size_t pairs, std::size_t reference, std::size_t missing, std::size_t extra,
                  double seconds, bool restricted = false) {
  cmp::PeerRow p;
  p.peer = name;
  p.ran = true;
  p.pairs = pairs, p.reference = reference, p.missing = missing, p.extra = extra, p.seconds = seconds;
  p.restricted = restricted;
  return p;
}

TEST(BenchIntersect, SentencesFromTallies) {
  const auto row = row_of(173, 0.5);
  EXPECT_EQ(cmp::peer_sentence(row, peer("CGAL PMP Epick", 173, 173, 0, 0, 1.0)),
            "CGAL PMP Epick: 173 pairs, the same as rayproof's 173; its time 2.00x rayproof's (rayproof faster).");
  EXPECT_EQ(cmp::peer_sentence(row, peer("FCL", 170, 173, 5, 2, 0.25)),
            "FCL: 170 pairs against rayproof's 173: 5 of rayproof's missing, 2 not in rayproof's exact set; its time "
            "0.50x rayproof's (rayproof slower).");
  // Decided on the printed ratio: 0.999 prints as 1.00x.
  EXPECT_EQ(cmp::peer_sentence(row, peer("CGAL PMP Epeck", 173, 173, 0, 0, 0.4995)),
            "CGAL PMP Epeck: 173 pairs, the same as rayproof's 173; its time 1.00x rayproof's (the same to two digits).");
  EXPECT_EQ(cmp::peer_sentence(row, peer("Open3D", 138, 140, 2, 0, 5.0, true)),
            "Open3D: it skips pairs that share a vertex index, so it is compared with the 140 of rayproof's 173 pairs "
            "that share none; 138 pairs against rayproof's 140: 2 of rayproof's missing, 0 not in rayproof's exact "
            "set; its time 10.00x rayproof's (rayproof faster).");
  EXPECT_EQ(cmp::peer_sentence(row_of(0, 0), peer("FCL", 0, 0, 0, 0, 1.0)),
            "FCL: 0 pairs, the same as rayproof's 0; no time ratio (rayproof's time is not positive).");
  cmp::PeerRow off;
  off.peer = "Open3D";
  off.note = "skipped: over 20000 triangles (it tests every pair; --open3d-max)";
  EXPECT_EQ(cmp::peer_sentence(row, off), "Open3D: skipped: over 20000 triangles (it tests every pair; --open3d-max).");
  EXPECT_EQ(cmp::time_ratio_text(3.0, 1.5), "2.00x");
  EXPECT_EQ(cmp::time_ratio_text(3.0, 0.0), "n/a");
}

TEST(BenchIntersect, ScopeAndDifferences) {
  rayproof::mesh::Mesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}, {4, 3, 0}, {3, 1, 0}};
  // (0, 1) share an edge, (0, 2) a vertex, (2, 2) a zero-area triangle alone, (1, 2) share index 3.
  const std::vector<rayproof::TrianglePair> pairs = {{0, 1}, {0, 2}, {1, 2}, {2, 2}};
  EXPECT_TRUE(cmp::pairs_sharing_no_index(m, pairs).empty());
  m.triangles[2] = {4, 4, 4};
  const std::vector<rayproof::TrianglePair> want = {{0, 2}, {1, 2}};  // (2, 2) stays out
  EXPECT_EQ(cmp::pairs_sharing_no_index(m, pairs), want);
  const std::vector<rayproof::TrianglePair> other = {{0, 1}, {0, 3}};
  EXPECT_EQ(cmp::pairs_missing_from(pairs, other), 3U);
  EXPECT_EQ(cmp::pairs_missing_from(other, pairs), 1U);
}

TEST(BenchIntersect, GeneratedMeshesHaveTheirContacts) {
  for (const auto& g : cmp::generated_intersect_meshes()) {
    cmp::IntersectBenchOptions opt;
    opt.repeat = 1;
    opt.peers = false;
    const auto row = cmp::self_intersect_row(g.name, g.mesh, opt);
    EXPECT_GT(row.pairs, 0U) << g.name;
    EXPECT_TRUE(row.peers.empty());
  }
}

/// Two unit boxes overlapping by half in x, as one mesh of 24 triangles.
std::string two_boxes_off() {
  std::string s = "OFF\n16 24 0\n";
  for (double x0 : {0.0, 0.5})
    for (int i = 0; i < 8; ++i)
      s += std::to_string(x0 + (i & 1)) + " " + std::to_string(i >> 1 & 1) + " " + std::to_string(i >> 2 & 1) + "\n";
  const int t[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                        {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (int first : {0, 8})
    for (const auto& f : t)
      s += "3 " + std::to_string(f[0] + first) + " " + std::to_string(f[1] + first) + " " + std::to_string(f[2] + first) + "\n";
  return s;
}

TEST(BenchIntersect, TinyMeshEndToEnd) {
  const auto boxes = write_file("boxes.off", two_boxes_off());
  const auto count = run_rayproof("intersect " + boxes.string() + " --count");
  ASSERT_EQ(count.status, 0) << count.err;
  const std::string n = count.out.substr(0, count.out.find('\n'));
  ASSERT_NE(n, "0");
  const auto r = run_rayproof("bench intersect " + boxes.string() + " --repeat 1");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("== boxes.off (24 triangles)"), std::string::npos) << r.out;
  // Each peer either agrees with rayproof's exact pairs or says why it did not run.
  const bool cgal = r.out.find("CGAL PMP Epick: " + n + " pairs, the same as rayproof's " + n + ";") != std::string::npos;
  const bool not_built = r.out.find("CGAL PMP Epick: not built in this build") != std::string::npos;
  EXPECT_TRUE(cgal || not_built) << r.out;
  if (cgal) {
    EXPECT_NE(r.out.find("CGAL PMP Epeck: " + n + " pairs, the same as rayproof's " + n + ";"), std::string::npos) << r.out;
  }
  EXPECT_NE(r.out.find("Open3D: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("== boxes.off + moved copy (24 x 24 triangles)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("FCL: "), std::string::npos) << r.out;
  // Without the interpreter the Open3D row says why, and the rest runs.
  const auto no_python = run_rayproof("bench intersect " + boxes.string() + " --repeat 1 --python /nonexistent/python3");
  ASSERT_EQ(no_python.status, 0) << no_python.err;
  EXPECT_NE(no_python.out.find("Open3D: not run: cannot start /nonexistent/python3: No such file or directory."),
            std::string::npos)
      << no_python.out;
  EXPECT_NE(no_python.out.find("FCL: "), std::string::npos) << no_python.out;
  const auto alone = run_rayproof("bench intersect " + boxes.string() + " --repeat 1 --rayproof-only");
  ASSERT_EQ(alone.status, 0) << alone.err;
  EXPECT_EQ(alone.out.find("CGAL PMP Epick"), std::string::npos) << alone.out;
}

TEST(BenchIntersect, ClearErrors) {
  auto r = run_rayproof("bench intersect /nonexistent/m.off");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("rayproof bench intersect: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
  const auto bad = write_file("bad.off", "OFF\n3 1 0\n0 0 0\n1 0\n");
  r = run_rayproof("bench intersect " + bad.string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("rayproof bench intersect: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bad.off"), std::string::npos) << r.err;
  const auto nan = write_file("nan.off", "OFF\n3 1 0\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n");
  r = run_rayproof("bench intersect " + nan.string() + " --rayproof-only");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("rayproof bench intersect: "), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("CGAL"), std::string::npos);
  r = run_rayproof("bench intersect " + bad.string() + " --repeat 0");
  EXPECT_NE(r.status, 0);
}

}  // namespace
