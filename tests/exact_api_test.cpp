/// rayproof/verify/exact.h, the typed exact API: the shared sample bit for bit (class, T, T2 and the sign of
/// zeros), the screening of docs/cases.md (invalid before degenerate), barycentrics rounded to nearest
/// on the generator's triangle families (a GMP oracle computed here), and concurrent calls giving
/// the serial answers.
#include "rayproof/verify/exact.h"

#include <gtest/gtest.h>
#include <mpfr.h>

#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include "api_cases.h"
#include "methods/method.h"

namespace rayproof {
namespace {

using api_test::same;

TEST(ExactApi, SampleBitForBit) {
  const api_test::Sample s = api_test::load_sample();
  ASSERT_EQ(s.cases.size(), s.expected.size());
  for (std::size_t i = 0; i < s.cases.size(); ++i) {
    const io::Case& c = s.cases[i];
    const io::CaseResult& want = s.expected[i];
    api_test::visit(c, [&](const auto& ray, const auto& prim) {
      const auto got = exact::intersect(ray, prim);
      const io::CaseResult r = make_result(c.kind, got.contact, got.t, got.t2);
      EXPECT_EQ(io::format_result(r), io::format_result(want)) << io::format_case(c);
      if (r.t && want.t) {
        EXPECT_EQ(std::signbit(*r.t), std::signbit(*want.t)) << io::format_case(c);
      }
      if (r.t2 && want.t2) {
        EXPECT_EQ(std::signbit(*r.t2), std::signbit(*want.t2)) << io::format_case(c);
      }
    });
  }
}

TEST(ExactApi, Screening) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const Ray<double> ray{{0, 0, -5}, {0, 0, 1}};
  EXPECT_EQ(exact::intersect(Ray<double>{{0, 0, 0}, {0, 0, 0}}, Sphere<double>{{0, 0, 0}, 1}).contact, Contact::invalid);
  EXPECT_EQ(exact::intersect(Ray<double>{{nan, 0, 0}, {0, 0, 1}}, Plane<double>{{0, 0, 0}, {0, 0, 1}}).contact,
            Contact::invalid);
  EXPECT_EQ(exact::intersect(ray, Sphere<double>{{0, 0, 0}, -1}).contact, Contact::invalid);
  EXPECT_EQ(exact::intersect(ray, Sphere<double>{{0, 0, 0}, -0.0}).contact, Contact::degenerate);  // -0 is not < 0
  // invalid wins over degenerate: a zero radius with an infinite centre.
  EXPECT_EQ(exact::intersect(ray, Sphere<double>{{inf, 0, 0}, 0}).contact, Contact::invalid);
  EXPECT_EQ(exact::intersect(ray, Ellipsoid<double>{{0, 0, 0}, {1, 0, 1}}).contact, Contact::degenerate);
  EXPECT_EQ(exact::intersect(ray, Ellipsoid<double>{{0, 0, 0}, {1, -1, 0}}).contact, Contact::invalid);
  EXPECT_EQ(exact::intersect(ray, Box<double>{{0, 0, 0}, {-1, 1, 1}}).contact, Contact::invalid);
  EXPECT_EQ(exact::intersect(ray, Disk<double>{{0, 0, 0}, {0, 0, 0}, 1}).contact, Contact::degenerate);
  EXPECT_EQ(exact::intersect(ray, Plane<double>{{0, 0, 0}, {0, 0, 0}}).contact, Contact::degenerate);
  EXPECT_EQ(exact::intersect(ray, Triangle<double>{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}).contact, Contact::degenerate);
  EXPECT_EQ(exact::intersect(ray, Triangle<double>{{0, 0, 0}, {1, 1, 1}, {2, 2, inf}}).contact, Contact::invalid);
  // A flat box (lo = hi on z) is crossed at one point: a graze at t = 5, not degenerate.
  const Hit<double> flat = exact::intersect(ray, Box<double>{{-1, -1, 0}, {1, 1, 0}});
  EXPECT_EQ(flat.contact, Contact::graze);
  EXPECT_EQ(flat.t, 5.0);
  EXPECT_EQ(flat.t2, 5.0);
  // Classes without t carry NaN; a triangle miss carries no barycentrics.
  const TriangleHit<double> miss = exact::intersect(ray, Triangle<double>{{5, 5, 0}, {6, 5, 0}, {5, 6, 0}});
  EXPECT_EQ(miss.contact, Contact::miss);
  EXPECT_TRUE(std::isnan(miss.t) && std::isnan(miss.t2) && std::isnan(miss.b1) && std::isnan(miss.b2));
  // A vertex hit: barycentrics exactly (0, 1) for p1.
  const TriangleHit<double> vtx = exact::intersect(ray, Triangle<double>{{1, 0, 0}, {0, 0, 0}, {0, 1, 0}});
  EXPECT_EQ(vtx.contact, Contact::vertex);
  EXPECT_EQ(vtx.t, 5.0);
  EXPECT_EQ(vtx.b1, 1.0);
  EXPECT_EQ(vtx.b2, 0.0);
}

TEST(ExactApi, TriangleFamiliesBarycentricsRoundedToNearest) {
  std::size_t contacts = 0;
  for (const gen::Family* f : api_test::triangle_families())
    for (const auto p : {gen::Precision::float32, gen::Precision::float64})
      for (const io::Case& c : gen::generate(*f, 100, 5, p)) {
        const Ray<double> ray = ray_of<double>(c);
        const Triangle<double> tri = triangle_of<double>(c);
        const TriangleHit<double> h = exact::intersect(ray, tri);
        const Contact k = h.contact;
        if (k != Contact::interior && k != Contact::edge && k != Contact::vertex && k != Contact::behind) {
          EXPECT_TRUE(std::isnan(h.b1) && std::isnan(h.b2)) << io::format_case(c);
          continue;
        }
        ++contacts;
        const auto [b1, b2] = api_test::exact_barycentrics(ray, tri);
        EXPECT_TRUE(api_test::rounded_to_nearest(h.b1, b1)) << io::format_case(c) << " b1 " << h.b1;
        EXPECT_TRUE(api_test::rounded_to_nearest(h.b2, b2)) << io::format_case(c) << " b2 " << h.b2;
      }
  EXPECT_GT(contacts, 500U);
}

// The documentation says concurrent calls are safe: MPFR's exponent range, which the rounding
// changes and restores, must be per thread. Two threads over the sample give the serial answers.
TEST(ExactApi, ConcurrentCallsGiveTheSerialAnswers) {
  EXPECT_TRUE(mpfr_buildopt_tls_p()) << "MPFR built without thread-local state: exact::intersect is not thread-safe";
  const api_test::Sample s = api_test::load_sample();
  auto run = [&s](std::vector<std::string>& out) {
    for (const io::Case& c : s.cases)
      api_test::visit(c, [&](const auto& ray, const auto& prim) {
        const auto h = exact::intersect(ray, prim);
        out.push_back(io::format_result(make_result(c.kind, h.contact, h.t, h.t2)));
      });
  };
  std::vector<std::string> serial, a, b;
  run(serial);
  std::thread ta([&] { for (int i = 0; i < 3; ++i) { a.clear(); run(a); } });
  std::thread tb([&] { for (int i = 0; i < 3; ++i) { b.clear(); run(b); } });
  ta.join();
  tb.join();
  EXPECT_EQ(a, serial);
  EXPECT_EQ(b, serial);
}

}  // namespace
}  // namespace rayproof
