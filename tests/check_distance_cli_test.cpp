// rayproof check --distance: programs speaking the distance line protocol, judged on a mesh file.
// The numpy example is caught (far points overflow to inf, a subnormal distance rounds to 0); the
// example wrapping `rayproof distance` has no finding, signed or not, with closest points and
// triangles or not; wrong closest points and triangles are counted; hangs and unreadable answers
// are reported and the run goes on.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "cli_support.h"
#include "judge_report_support.h"

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
  for (const char* sign : {"", " --signed", " --closest", " --signed --closest"}) {
    const std::string s = sign;
    const auto e = run_rayproof("check --distance 'exact=/usr/bin/python3 " + example("rayproof_distance.py") + " " +
                                RAYPROOF_BIN + sign + "' --mesh " + mesh.string() + " --distance-points 100" +
                                (s.find("--signed") != std::string::npos ? " --distance-signed" : ""));
    EXPECT_EQ(e.status, 0) << sign << e.err << e.out;
    if (s.find("--closest") != std::string::npos) {
      EXPECT_GT(count_of(e.out, "exact", "closest_points"), 100u) << e.out;
      EXPECT_EQ(count_of(e.out, "exact", "triangle_ids"), count_of(e.out, "exact", "closest_points")) << e.out;
    }
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

TEST(CheckDistanceCli, ClosestPointColumnsAndFloatPrecision) {
  const auto mesh = write_file("cube.off", kCube);
  const auto r = run_rayproof("check --distance 'cols=while read l; do echo 1 0.5 0.5 7 99; done' --distance "
                              "'pt=while read l; do echo 1 0.5 0.5 1; done' --mesh " + mesh.string() +
                              " --distance-points 10 --distance-sets random --json --distance-precision float");
  ASSERT_EQ(r.status, 1) << r.err;
  const nlohmann::json out = nlohmann::json::parse(r.out);
  const nlohmann::json& cols = out["functions"][0];
  EXPECT_EQ(cols["precision"], "float");
  EXPECT_EQ(cols["closest_points"], 10);
  EXPECT_EQ(cols["closest_off_mesh"], 10);  // 6 above the cube
  EXPECT_EQ(cols["triangle_ids"], 10);
  EXPECT_EQ(cols["wrong_triangle"], 10);  // the cube has 12
  const nlohmann::json& pt = out["functions"][1];
  EXPECT_EQ(pt["closest_points"], 10);
  EXPECT_EQ(pt["closest_off_mesh"], 0);  // on the top face
  EXPECT_EQ(pt["triangle_ids"], 0);
  EXPECT_EQ(pt["wrong_triangle"], 0);
  const auto bad = run_rayproof("check --distance 'x=while read l; do echo 1 2 3; done' --mesh " + mesh.string() +
                                " --distance-points 3 --distance-sets random");
  EXPECT_NE(bad.out.find("event: unreadable answer '1 2 3'"), std::string::npos) << bad.out;
}

// --out DIR: report.md holds the counts --json gives for a function answering 0 everywhere (right
// at the vertices, wrong at random points, a number at invalid points), beside rayproof's own exact
// distance judged the same way with no finding; a DIR that cannot be made is refused.
TEST(CheckDistanceCli, OutWritesTheReportBesideRayproofsOwn) {
  const auto mesh = write_file("cube.off", kCube);
  const auto dir = testing::scratch_dir() / "distance_report";
  const std::string args = "check --distance 'zero=while read l; do echo 0; done' --mesh " + mesh.string() +
                           " --distance-points 10 --distance-sets vertex,random,invalid --distance-signed";
  const nlohmann::json run = testing::run_writing_report(args, dir);
  ASSERT_FALSE(run.empty());
  EXPECT_EQ(run["over_tolerance"], 10);
  EXPECT_EQ(run["invalid_number"], run["invalid_points"]);
  EXPECT_EQ(run["sets"]["vertex"]["findings"], 0);
  testing::expect_report_matches_json(dir, run, "zero", mesh.string(), "points", run["findings"].get<std::uint64_t>(),
                                      {"points", "surface", "over_1ulp", "over_tolerance", "max_ulps", "wrong_sign",
                                       "closest_points", "wrong_triangle", "garbage", "failures", "invalid_points",
                                       "invalid_number", "invalid_failures", "findings"});
  // rayproof's own answers its closest points and triangles too: judged, and right.
  const auto own = testing::markdown_row(testing::slurp(dir / "report.md"), 0, "rayproof exact");
  ASSERT_FALSE(own.empty());
  EXPECT_EQ(own.at("closest_points"), own.at("triangle_ids"));
  EXPECT_EQ(own.at("closest_points"), std::to_string(run["points"].get<int>() - run["invalid_points"].get<int>()));
  testing::expect_unwritable_out_refused(args);
}

/// A distance written the naive way, for boxes: outside, sqrt(dx*dx + dy*dy + dz*dz) of the box's
/// excess per axis (the squares overflow to inf beyond 2^512, are subnormal below 2^-511); inside,
/// the least distance to a side.
const char* const kNaiveBoxDistance = R"(import math, sys
def words():
    return sys.stdin.readline().split()
words()
V = [tuple(map(float, words())) for _ in range(int(words()[1]))]
for _ in range(int(words()[1])):
    words()
lo = [min(v[i] for v in V) for i in range(3)]
hi = [max(v[i] for v in V) for i in range(3)]
while True:
    w = words()
    if not w or w[0] != "points":
        break
    out = []
    for _ in range(int(w[1])):
        p = [float(x) for x in words()]
        if not all(math.isfinite(c) for c in p):
            out.append("nan")
            continue
        d = [max(lo[i] - p[i], 0.0, p[i] - hi[i]) for i in range(3)]
        if any(d):
            out.append(repr(math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])))
        else:
            out.append(repr(min(min(p[i] - lo[i], hi[i] - p[i]) for i in range(3))))
    sys.stdout.write("".join(a + "\n" for a in out))
    sys.stdout.flush()
)";

// --distance-scale: the cube times 2^600 and 2^-600, exactly. rayproof's own distance (with its
// closest points and triangles) has no finding there and every set is as large as at scale 1; the
// naive distance above overflows (2^600) or underflows (2^-600) off the surface and is caught on
// the random points, where it is right at scale 1 up to its roundings. A scale that is not a power
// of two, that overflows a vertex or makes one subnormal (or leaves float's range, for a float
// function) is refused.
TEST(CheckDistanceCli, ExtremeScalesAreJudgedExactly) {
  if (!have_numpy()) GTEST_SKIP() << "/usr/bin/python3 has no numpy";
  const auto mesh = write_file("cube.off", kCube);
  const auto naive = write_file("naive_box_distance.py", kNaiveBoxDistance);
  const auto judged = [&](const std::string& fn, const std::string& scale) {
    const auto r = run_rayproof("check --distance '" + fn + "' --mesh " + mesh.string() +
                                " --distance-points 100 --distance-max-per-set 100 --json --distance-scale " + scale);
    EXPECT_NE(r.status, 2) << scale << r.err;
    return std::pair{r.status, nlohmann::json::parse(r.out)["functions"][0]};
  };
  const std::string exact = "exact=/usr/bin/python3 " + example("rayproof_distance.py") + " " + RAYPROOF_BIN + " --closest";
  const auto [status1, one] = judged(exact, "1");
  EXPECT_EQ(status1, 0) << one.dump(1);
  const auto [naive_status1, naive_one] = judged("naive=/usr/bin/python3 " + naive.string(), "1");
  for (const char* scale : {"2^600", "2^-600", "0x1p-600"}) {
    const auto [status, run] = judged(exact, scale);
    EXPECT_EQ(status, 0) << scale << run.dump(1);
    EXPECT_EQ(run["findings"], 0) << scale;
    EXPECT_EQ(run["mesh"], mesh.string() + (scale[0] == '0' ? "*2^-600" : std::string("*") + scale));
    EXPECT_EQ(run["points"], one["points"]) << scale;
    EXPECT_EQ(run["surface"], one["surface"]) << scale;
    EXPECT_EQ(run["closest_points"], one["closest_points"]) << scale;
    ASSERT_EQ(run["sets"].size(), one["sets"].size()) << scale;
    for (const auto& [set, counts] : one["sets"].items()) EXPECT_EQ(run["sets"][set]["points"], counts["points"]) << scale << " " << set;
    const auto [naive_status, naive_run] = judged("naive=/usr/bin/python3 " + naive.string(), scale);
    EXPECT_EQ(naive_status, 1) << scale;
    EXPECT_GT(naive_run["sets"]["random"]["findings"].get<int>(), naive_one["sets"]["random"]["findings"].get<int>())
        << scale << naive_run.dump(1);
  }
  for (const char* bad : {"3", "2^1.5", "-4", "0", "inf", "2^", "x"}) {
    const auto r = run_rayproof("check --distance x=cat --mesh " + mesh.string() + " --distance-scale=" + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find("is not a power of two"), std::string::npos) << bad << r.err;
  }
  for (const char* bad : {"2^1024", "2^-1023", "2^200 --distance-precision float"}) {
    const auto r = run_rayproof("check --distance x=cat --mesh " + mesh.string() + " --distance-scale " + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find("the scaled mesh would not be exact"), std::string::npos) << bad << r.err;
  }
}

TEST(CheckDistanceCli, BadUsageIsRefused) {
  const auto mesh = write_file("cube.off", kCube);
  EXPECT_EQ(run_rayproof("check --distance 'x=cat'").status, 2);
  EXPECT_EQ(run_rayproof("check --distance nocommand --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --distance x=cat --contains y=cat --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --distance x=cat --distance-rel-tol -1 --mesh " + mesh.string()).status, 2);
  EXPECT_EQ(run_rayproof("check --distance x=cat --distance-sets nope --mesh " + mesh.string()).status, 2);
  const auto p = run_rayproof("check --distance x=cat --distance-precision half --mesh " + mesh.string());
  EXPECT_EQ(p.status, 2);
  EXPECT_NE(p.err.find("--distance-precision 'half' is neither float nor double"), std::string::npos) << p.err;
}

}  // namespace
}  // namespace rayproof
