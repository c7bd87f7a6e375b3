/// rayproof/verify/gtest.h: EXPECT_RAY_HIT_MATCHES_EXACT passes on good kernels (the exact and certified
/// APIs, a float kernel on an exactly representable case) and fails, non-fatally, on bad ones with
/// a message that holds the reproducer case line (which reads back to the same inputs), the exact
/// and kernel answers and the ulp distance.
#include "rayproof/verify/gtest.h"

#include <gmock/gmock.h>
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <variant>

#include "io/case_file.h"
#include "rayproof/certified/intersect.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle.h"

namespace rayproof {
namespace {

Triangle<double> detail_wide(const Triangle<float>& t) { return gtest::detail::wide(t); }

using ::testing::HasSubstr;

const Ray<double> kRay{{0.25, 0.25, -1}, {0, 0, 1}};
const Triangle<double> kTri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};  // hit at t = 1, b = (0.5, 0.25, 0.25)

auto exact_kernel = [](const auto& ray, const auto& prim) { return exact::intersect(ray, prim); };
auto certified_kernel = [](const auto& ray, const auto& prim) { return certified::intersect(ray, prim); };

/// The exact answer with t moved by `ulps` doubles upwards.
auto off_by(int ulps) {
  return [ulps](const auto& ray, const auto& prim) {
    auto h = exact::intersect(ray, prim);
    for (int i = 0; i < ulps; ++i) h.t = std::nextafter(h.t, INFINITY);
    return h;
  };
}

/// The exact answer with the class replaced.
auto wrong_class(Contact c) {
  return [c](const auto& ray, const auto& prim) {
    auto h = exact::intersect(ray, prim);
    h.contact = c;
    return h;
  };
}

TEST(GTestHelpers, PassesOnGoodKernels) {
  EXPECT_RAY_HIT_MATCHES_EXACT(exact_kernel, kRay, kTri, 0);
  EXPECT_RAY_HIT_MATCHES_EXACT(certified_kernel, kRay, kTri, 1);
  // Header-only kernels, in float and double: the case is exact in both.
  auto mt = [](const auto& ray, const auto& prim) { return intersect(ray, prim); };
  EXPECT_RAY_HIT_MATCHES_EXACT(mt, (Ray<float>{{0.25f, 0.25f, -1}, {0, 0, 1}}),
                               (Triangle<float>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), 0);
  ASSERT_RAY_HIT_MATCHES_EXACT(mt, (Ray<double>{{0, 0, -5}, {0, 0, 1}}), (Sphere<double>{{0, 0, 0}, 1}), 0);
  // Within the tolerance: 2 ulps off with max 2.
  EXPECT_RAY_HIT_MATCHES_EXACT(off_by(2), kRay, kTri, 2);
}

TEST(GTestHelpers, FailsOnBadKernelsWithTheCaseAndTheUlps) {
  EXPECT_NONFATAL_FAILURE(EXPECT_RAY_HIT_MATCHES_EXACT(off_by(3), kRay, kTri, 2), "t off by 3 ulps (max 2)");
  EXPECT_NONFATAL_FAILURE(EXPECT_RAY_HIT_MATCHES_EXACT(off_by(3), kRay, kTri, 2),
                          "case:   triangle 0.25 0.25 -1 0 0 1 0 0 0 1 0 0 0 1 0");
  EXPECT_NONFATAL_FAILURE(EXPECT_RAY_HIT_MATCHES_EXACT(wrong_class(Contact::edge), kRay, kTri, 2),
                          "class edge != exact interior");

  const std::string msg = rayproof::gtest::matches_exact(off_by(3), kRay, kTri, 2).message();
  EXPECT_THAT(msg, HasSubstr("exact:  interior 1 -"));
  EXPECT_THAT(msg, HasSubstr("kernel: interior 1.0000000000000007 -  (t: 3 ulps of double)"));
  // Two-valued kinds: t2 is checked too.
  auto t2_off = [](const auto& ray, const auto& prim) {
    auto h = exact::intersect(ray, prim);
    h.t2 = std::nextafter(h.t2, -INFINITY);
    return h;
  };
  const std::string m2 =
      rayproof::gtest::matches_exact(t2_off, Ray<double>{{0, 0, -5}, {0, 0, 1}}, Sphere<double>{{0, 0, 0}, 1}, 0).message();
  EXPECT_THAT(m2, HasSubstr("t2 off by 1 ulp (max 0)"));
  EXPECT_THAT(m2, HasSubstr("exact:  hit 4 6"));
  EXPECT_THAT(m2, HasSubstr("case:   sphere 0 0 -5 0 0 1 0 0 0 1"));
  // A fatal variant stops the test: checked with EXPECT_FATAL_FAILURE on a helper.
  EXPECT_FATAL_FAILURE(
      ASSERT_RAY_HIT_MATCHES_EXACT(wrong_class(Contact::miss), kRay, kTri, 0), "class miss != exact interior");
}

// The reproducer line reads back (docs/cases.md) to the same doubles, also for awkward ones.
TEST(GTestHelpers, CaseLineReadsBackExactly) {
  const Ray<double> ray{{0.1, -0.0, 1e-310}, {std::nextafter(1.0, 2.0), 3e300, -1.0 / 3}};
  const Triangle<double> tri{{1e-5, 2.5, -7}, {0.3, 0.7, 1e22}, {5e-324, -2, 0x1.fffffffffffffp+1023}};
  const std::string msg = rayproof::gtest::matches_exact(wrong_class(Contact::error), ray, tri, 0).message();
  const auto at = msg.find("case:   ");
  ASSERT_NE(at, std::string::npos) << msg;
  const std::string line = msg.substr(at + 8, msg.find('\n', at) - at - 8);
  std::string family;
  const auto entry = io::parse_case_line(line, 1, family);
  ASSERT_TRUE(entry.has_value()) << line;
  const auto* c = std::get_if<io::Case>(&*entry);
  ASSERT_NE(c, nullptr) << line;
  const double want[15] = {ray.o.x, ray.o.y, ray.o.z, ray.d.x, ray.d.y, ray.d.z, tri.p0.x, tri.p0.y,
                           tri.p0.z, tri.p1.x, tri.p1.y, tri.p1.z, tri.p2.x, tri.p2.y, tri.p2.z};
  for (std::size_t i = 0; i < 15; ++i) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(c->v[i]), std::bit_cast<std::uint64_t>(want[i])) << line << " field " << i;
  }
}

// --- triangle pairs: EXPECT_TRITRI_MATCHES_EXACT ------------------------------------------------------

// b's vertex (1, 1, 0) lies inside a: touching by construction (docs/tritri.md's example).
const Triangle<double> kA{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}};
const Triangle<double> kB{{1, 1, 0}, {1, 1, 1}, {2, 1, 1}};
const Triangle<double> kFar{{10, 10, 10}, {11, 10, 10}, {10, 11, 10}};

TEST(GtestTriTri, PassesOnExactAnswersBoolOrClass) {
  auto meets = [](const auto& a, const auto& b) { return exact::tritri_meets(a, b); };
  auto cls = [](const auto& a, const auto& b) { return exact::tritri(a, b); };
  EXPECT_TRITRI_MATCHES_EXACT(meets, kA, kB);
  EXPECT_TRITRI_MATCHES_EXACT(meets, kA, kFar);
  EXPECT_TRITRI_MATCHES_EXACT(cls, kA, kB);
  // A float kernel: the pair is exact in float, and widened for the exact answer.
  auto meets_f = [](const Triangle<float>& a, const Triangle<float>& b) {
    return exact::tritri_meets(detail_wide(a), detail_wide(b));
  };
  const Triangle<float> af{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}}, bf{{1, 1, 0}, {1, 1, 1}, {2, 1, 1}};
  EXPECT_TRITRI_MATCHES_EXACT(meets_f, af, bf);
}

TEST(GtestTriTri, FailsWithTheCaseLineTheExactAndTheKernelAnswer) {
  auto never = [](const auto&, const auto&) { return false; };
  auto crossing = [](const auto&, const auto&) { return TriTri::crossing; };
  EXPECT_NONFATAL_FAILURE(EXPECT_TRITRI_MATCHES_EXACT(never, kA, kB), "exact:  meets (touching)");
  EXPECT_NONFATAL_FAILURE(EXPECT_TRITRI_MATCHES_EXACT(never, kA, kB), "kernel: disjoint");
  EXPECT_NONFATAL_FAILURE(EXPECT_TRITRI_MATCHES_EXACT(crossing, kA, kB), "exact:  touching\n  kernel: crossing");
  auto always = [](const auto&, const auto&) { return true; };
  EXPECT_NONFATAL_FAILURE(EXPECT_TRITRI_MATCHES_EXACT(always, kA, kFar), "exact:  disjoint");

  // The case line reads back to the same pair.
  const auto r = gtest::tritri_matches_exact(never, kA, kB);
  ASSERT_FALSE(r);
  const std::string msg = r.message();
  const auto at = msg.find("case:   ");
  ASSERT_NE(at, std::string::npos) << msg;
  const std::string line = msg.substr(at + 8, msg.find('\n', at) - at - 8);
  std::string family;
  const auto entry = io::parse_case_line(line, 1, family);
  ASSERT_TRUE(entry && std::holds_alternative<io::Case>(*entry)) << line;
  const auto& c = std::get<io::Case>(*entry);
  EXPECT_EQ(c.kind, io::Kind::tritri);
  const double want[18] = {0, 0, 0, 4, 0, 0, 0, 4, 0, 1, 1, 0, 1, 1, 1, 2, 1, 1};
  for (int i = 0; i < 18; ++i) EXPECT_EQ(c.v[static_cast<std::size_t>(i)], want[i]) << i;
}

}  // namespace
}  // namespace rayproof
