/// rayproof/certified/intersect.h, the typed certified API: over the shared sample, certified::intersect has
/// exactly the expected class and t, t2 within one ulp of the expected (exact) values, and the
/// header-only try_intersect is either undecided or the same answer; the fallback count is the
/// number of undecided calls; on the generator's triangle families the barycentrics are within
/// kBarycentricError of the exact ones (an oracle computed here with GMP rationals), with exact
/// zeros and ones on edges and vertices.
#include "rayproof/certified/intersect.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <thread>

#include "api_cases.h"
#include "methods/method.h"
#include "rayproof/verify/exact.h"

namespace rayproof {
namespace {

using api_test::same;

bool same_answer(const Hit<double>& a, const Hit<double>& b) {
  return a.contact == b.contact && same(a.t, b.t) && same(a.t2, b.t2);
}
bool same_answer(const TriangleHit<double>& a, const TriangleHit<double>& b) {
  return a.contact == b.contact && same(a.t, b.t) && same(a.t2, b.t2) && same(a.b1, b.b1) && same(a.b2, b.b2);
}

/// Within one ulp, where both are present (a NaN on one side only is a failure).
bool within_one_ulp(std::optional<double> got, std::optional<double> want) {
  if (got.has_value() != want.has_value()) return false;
  return !got || ulp_distance(*got, *want) <= 1;
}

TEST(CertifiedApi, SampleExactClassTWithinOneUlpTryIntersectUndecidedOrEqual) {
  const api_test::Sample s = api_test::load_sample();
  ASSERT_EQ(s.cases.size(), s.expected.size());
  std::size_t decided = 0, undecided = 0;
  const std::uint64_t fallbacks_before = certified::fallback_count();
  for (std::size_t i = 0; i < s.cases.size(); ++i) {
    const io::Case& c = s.cases[i];
    const io::CaseResult& want = s.expected[i];
    api_test::visit(c, [&](const auto& ray, const auto& prim) {
      const auto got = certified::intersect(ray, prim);
      const io::CaseResult r = make_result(c.kind, got.contact, got.t, got.t2);
      EXPECT_EQ(got.contact, want.contact) << io::format_case(c);
      EXPECT_TRUE(within_one_ulp(r.t, want.t)) << io::format_case(c) << ": t " << got.t;
      EXPECT_TRUE(within_one_ulp(r.t2, want.t2)) << io::format_case(c) << ": t2 " << got.t2;
      if (const auto core = certified::try_intersect(ray, prim)) {
        ++decided;
        EXPECT_TRUE(same_answer(*core, got)) << io::format_case(c);
      } else {
        ++undecided;
      }
    });
  }
  EXPECT_EQ(certified::fallback_count() - fallbacks_before, undecided);
  EXPECT_GT(decided, s.cases.size() / 2);  // the filters decide the bulk; otherwise the check above is empty
}

// Concurrent calls: every thread gets the serial answers, and its own fallback count (thread-local)
// is the serial count, whatever the other thread does.
TEST(CertifiedApi, ConcurrentCallsAndPerThreadFallbackCount) {
  // The sample, and extreme magnitudes (subnormal, near overflow), where the filters leave work for GMP.
  std::vector<io::Case> cases = api_test::load_sample().cases;
  for (const char* family : {"tri_extreme_scale", "sph_generic"}) {
    const gen::Family* f = gen::find_family(family);
    ASSERT_NE(f, nullptr) << family;
    const auto more = gen::generate(*f, 200, 3, gen::Precision::float64);
    cases.insert(cases.end(), more.begin(), more.end());
  }
  auto run = [&cases](std::vector<std::string>& out) {
    const std::uint64_t before = certified::fallback_count();
    for (const io::Case& c : cases)
      api_test::visit(c, [&](const auto& ray, const auto& prim) {
        const auto h = certified::intersect(ray, prim);
        out.push_back(io::format_result(make_result(c.kind, h.contact, h.t, h.t2)));
      });
    return certified::fallback_count() - before;
  };
  std::vector<std::string> serial, a, b;
  const std::uint64_t fb = run(serial);
  std::uint64_t fa = 0, fbb = 0;
  std::thread ta([&] { fa = run(a); });
  std::thread tb([&] { fbb = run(b); });
  ta.join();
  tb.join();
  EXPECT_EQ(a, serial);
  EXPECT_EQ(b, serial);
  EXPECT_EQ(fa, fb);
  EXPECT_EQ(fbb, fb);
  EXPECT_GT(fb, 0U);  // the sample has cases only the fallback decides: the counts are not trivially 0
}

// Answers without a t carry NaN; hits carry finite t (and t2 for two-valued kinds).
TEST(CertifiedApi, UnusedFieldsAreNaN) {
  const Ray<double> ray{{0, 0, -1}, {0, 0, 1}};
  const auto miss = certified::intersect(ray, Sphere<double>{{5, 5, 5}, 1});
  EXPECT_EQ(miss.contact, Contact::miss);
  EXPECT_TRUE(std::isnan(miss.t) && std::isnan(miss.t2));
  const auto hit = certified::intersect(ray, Triangle<double>{{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}});
  EXPECT_EQ(hit.contact, Contact::interior);
  EXPECT_EQ(hit.t, 1.0);
  EXPECT_TRUE(std::isnan(hit.t2));
  // The plane point (0, 0) = 0.25 p0 + 0.25 p1 + 0.5 p2: exact in binary.
  EXPECT_EQ(hit.b1, 0.25);
  EXPECT_EQ(hit.b2, 0.5);
  const auto invalid = certified::intersect(Ray<double>{{0, 0, 0}, {0, 0, 0}}, Plane<double>{{0, 0, 1}, {0, 0, 1}});
  EXPECT_EQ(invalid.contact, Contact::invalid);
}

struct BaryStats {
  std::size_t contacts = 0, filter_decided = 0, wide_decided = 0, dd_decided = 0, expansion_decided = 0;
};

/// Each barycentric stage on its own: undecided, or within the bound of the oracle's values.
void check_stage(bool decided, double x1, double x2, const mpq_class& b1, const mpq_class& b2, Contact k,
                 const std::string& what) {
  if (!decided) return;
  const mpq_class bound(certified::kBarycentricError);
  EXPECT_LE(abs(mpq_class(x1) - b1), bound) << what << " b1 = " << x1;
  EXPECT_LE(abs(mpq_class(x2) - b2), bound) << what << " b2 = " << x2;
  if (k == Contact::edge || k == Contact::vertex) {
    EXPECT_TRUE(sgn(b1) != 0 || x1 == 0.0) << what;
    EXPECT_TRUE(sgn(b2) != 0 || x2 == 0.0) << what;
  }
}

/// One triangle case: class and t against exact::intersect; b1, b2 against the oracle.
void check_triangle(const io::Case& c, BaryStats& st) {
  const Ray<double> ray = ray_of<double>(c);
  const Triangle<double> tri = triangle_of<double>(c);
  const TriangleHit<double> got = certified::intersect(ray, tri), want = exact::intersect(ray, tri);
  const std::string line = io::format_case(c);
  ASSERT_EQ(got.contact, want.contact) << line;
  EXPECT_TRUE(std::isnan(want.t) ? std::isnan(got.t) : ulp_distance(got.t, want.t) <= 1) << line;
  EXPECT_TRUE(std::isnan(want.t2) ? std::isnan(got.t2) : ulp_distance(got.t2, want.t2) <= 1) << line;
  const auto core = certified::try_intersect(ray, tri);
  if (core) {
    EXPECT_TRUE(same_answer(*core, got)) << line;
  }
  const Contact k = got.contact;
  if (k != Contact::interior && k != Contact::edge && k != Contact::vertex && k != Contact::behind) {
    EXPECT_TRUE(std::isnan(got.b1) && std::isnan(got.b2)) << line;
    return;
  }
  ++st.contacts;
  st.filter_decided += core.has_value();
  const auto [b1, b2] = api_test::exact_barycentrics(ray, tri);
  double w1 = NAN, w2 = NAN, x1 = NAN, x2 = NAN;
  const bool wide = certified::detail::triangle_barycentrics_wide(ray, tri, k, w1, w2);
  const bool expn = certified::detail::triangle_barycentrics_expansion(ray, tri, k, x1, x2);
  st.wide_decided += wide;
#if RAYPROOF_FMA_PATH != 0
  if (certified::dd::available()) {
    double y1 = NAN, y2 = NAN;
    const bool ddok = certified::detail::triangle_barycentrics_dd(ray, tri, k, y1, y2);
    st.dd_decided += ddok;
    check_stage(ddok, y1, y2, b1, b2, k, line + " (double-double stage)");
  }
#endif
  st.expansion_decided += expn;
  check_stage(wide, w1, w2, b1, b2, k, line + " (Wide stage)");
  check_stage(expn, x1, x2, b1, b2, k, line + " (expansion stage)");
  const mpq_class bound(certified::kBarycentricError);
  for (const auto& [b, x, name] : {std::tuple{b1, got.b1, "b1"}, std::tuple{b2, got.b2, "b2"}}) {
    ASSERT_FALSE(std::isnan(x)) << line << " " << name;
    EXPECT_LE(abs(mpq_class(x) - b), bound) << line << " " << name << " = " << x << ", exact " << b.get_d();
    EXPECT_TRUE(x >= 0 && x <= 1) << line << " " << name;
    if (k == Contact::edge || k == Contact::vertex) {
      if (sgn(b) == 0) {
        EXPECT_EQ(x, 0.0) << line << " " << name;
      }
      if (b == 1) {
        EXPECT_EQ(x, 1.0) << line << " " << name;
      }
    }
  }
}

TEST(CertifiedApi, TriangleFamiliesBarycentricBound) {
  BaryStats st;
  std::size_t families = 0;
  for (const gen::Family* f : api_test::triangle_families()) {
    ++families;
    for (const auto p : {gen::Precision::float32, gen::Precision::float64})
      for (const io::Case& c : gen::generate(*f, 150, 11, p)) check_triangle(c, st);
  }
  EXPECT_GE(families, 10U);
  // The bound is exercised on both paths: the filter's (Wide intervals) and the exact fallback's.
  EXPECT_GT(st.filter_decided, st.contacts / 2);
  EXPECT_LT(st.filter_decided, st.contacts);
  EXPECT_GT(st.wide_decided, st.contacts / 2);
  EXPECT_GT(st.expansion_decided, st.contacts / 2);
  RecordProperty("contacts", static_cast<int>(st.contacts));
  RecordProperty("filter_decided", static_cast<int>(st.filter_decided));
  RecordProperty("wide_decided", static_cast<int>(st.wide_decided));
  RecordProperty("dd_decided", static_cast<int>(st.dd_decided));
  if (certified::dd::available()) {
    EXPECT_GT(st.dd_decided, st.contacts / 2);
  }
  RecordProperty("expansion_decided", static_cast<int>(st.expansion_decided));
}

}  // namespace
}  // namespace rayproof
