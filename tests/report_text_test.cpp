// Every sentence the report writes, built from known tallies and checked word for word.
#include "report/report_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace rayproof;
using report::Row;

namespace {

constexpr std::uint64_t kNaN = std::numeric_limits<std::uint64_t>::max();

/// A row of `cases` cases with `class_errors` false misses and the given t errors.
Row row(const std::string& method, const std::string& group, io::Kind kind, double ns, std::size_t cases,
        std::size_t class_errors, std::vector<std::uint64_t> ulps, Precision p = Precision::float64) {
  Row r;
  r.method = method;
  r.group = group;
  r.kind = kind;
  r.precision = p;
  r.ns_per_case = ns;
  r.stats.cases = cases;
  r.stats.false_miss = class_errors;
  r.stats.ulps = std::move(ulps);
  return r;
}

Promise exactness() { return Promise{true, Promise::NoFalseMiss::all, 1}; }

io::Case sphere_case() {
  io::Case c;
  c.kind = io::Kind::sphere;
  c.v = {0, 0, -5, 0, 0, 1, 0, 0, 0, 1};
  return c;
}

io::CaseResult hit(double t, double t2) {
  io::CaseResult r;
  r.contact = Contact::hit;
  r.t = t;
  r.t2 = t2;
  return r;
}

}  // namespace

TEST(ReportText, UlpsReadAsWhatTheyAre) {
  EXPECT_EQ(report::ulp_text(0, Precision::float64), "0");
  EXPECT_EQ(report::ulp_text(999999, Precision::float32), "999999");
  EXPECT_EQ(report::ulp_text(kNaN, Precision::float64), "NaN t");
  // 10^9 double ulps: at most 10^9 * 2^-52 = 2.2e-07 relative; in float, far beyond 2^23: leading bits.
  EXPECT_EQ(report::ulp_text(1000000000, Precision::float64), "1e+09 (rel. <= 2e-07)");
  EXPECT_EQ(report::ulp_text(1000000000, Precision::float32), "1e+09 (leading bits wrong)");
  // The ~4.5e18 of a t on the other side of zero.
  EXPECT_EQ(report::ulp_text(4500000000000000000ULL, Precision::float64), "4.5e+18 (leading bits wrong)");
  EXPECT_EQ(report::ulp_text((std::uint64_t{1} << 52) - 1, Precision::float64), "4.5e+15 (rel. <= 1e+00)");
}

TEST(ReportText, ErrorFreeCountsTBeyondTolerance) {
  const Row r = row("float", "ell_generic", io::Kind::ellipsoid, 10, 100, 0, {0, 3, 1200000000}, Precision::float32);
  EXPECT_FALSE(report::error_free(r.stats, 1));
  EXPECT_TRUE(report::error_free(r.stats, 1200000000));
  EXPECT_EQ(report::tolerance(Promise{}, 4), 4u);
  EXPECT_EQ(report::tolerance(exactness(), 4), 1u);
  Row nan = row("double", "g", io::Kind::triangle, 1, 10, 0, {0, kNaN});
  EXPECT_FALSE(report::error_free(nan.stats, 1000));
  Row failed = row("mine", "g", io::Kind::triangle, 1, 10, 0, {});
  failed.stats.kernel_failures = 1;
  EXPECT_FALSE(report::error_free(failed.stats, 1));
  EXPECT_FALSE(report::error_free(verify::Stats{}, 1)) << "no case is no evidence";
}

TEST(ReportText, KindSentencesJudgeTAndInvalidFamiliesLikeAnyOther) {
  using K = io::Kind;
  std::vector<Row> rows = {
      // ell_generic: float has the right classes but t off by 1.2e9 float ulps; certified is exact.
      row("float", "ell_generic", K::ellipsoid, 10, 500, 0, {0, 1200000000}, Precision::float32),
      row("certified", "ell_generic", K::ellipsoid, 400, 500, 0, {0, 1}),
      // invalid_ellipsoid: no t at all; float is cheapest and error-free, exact is not named.
      row("float", "invalid_ellipsoid", K::ellipsoid, 5, 80, 0, {}, Precision::float32),
      row("certified", "invalid_ellipsoid", K::ellipsoid, 6, 80, 0, {}),
      // ell_tangent_exact: float makes class errors, certified does not.
      row("float", "ell_tangent_exact", K::ellipsoid, 10, 500, 7, {0}, Precision::float32),
      row("certified", "ell_tangent_exact", K::ellipsoid, 500, 500, 0, {0}),
      // another kind is left out
      row("float", "tri_generic", K::triangle, 1, 500, 0, {0}, Precision::float32),
  };
  for (auto& r : rows)
    if (r.method == "certified") r.promise = exactness();
  const auto s = report::kind_sentences(K::ellipsoid, rows, 1);
  ASSERT_EQ(s.size(), 3u);
  // certified: (400*500 + 6*80 + 500*500) / 1080 = 417.11 ns per case.
  EXPECT_EQ(s[0], "The cheapest method error-free on every ellipsoid family (3) is `certified` at 417.1 ns per case.");
  EXPECT_EQ(s[1], "Family by family, the cheapest error-free method is `certified` on ell_generic, ell_tangent_exact; "
                  "`float` on invalid_ellipsoid.");
  EXPECT_EQ(s[2], "Where the cheapest method without a class error has t beyond tolerance: `float` on ell_generic (t off "
                  "by up to 1.2e+09 float ulps, leading bits wrong).");

  // With no error-free method anywhere, it says so; a family without one is named.
  std::vector<Row> bad = {row("float", "a", K::disk, 1, 10, 1, {}), row("float", "b", K::disk, 1, 10, 0, {0})};
  const auto t = report::kind_sentences(K::disk, bad, 1);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0], "No method was error-free on every disk family (2).");
  EXPECT_EQ(t[1], "Family by family, the cheapest error-free method is `float` on b; no method is error-free on a.");
  bad[1].stats.false_hit = 1;
  EXPECT_EQ(report::kind_sentences(K::disk, bad, 1)[1], "Family by family, no method is error-free on any family.");
  EXPECT_TRUE(report::kind_sentences(K::box, bad, 1).empty());
}

TEST(ReportText, PromiseSentencesSayKeptOrBrokenWithTheCounts) {
  using K = io::Kind;
  std::vector<Row> rows = {row("robust", "tri_edge", K::triangle, 1, 500, 3, {}), row("robust", "box_graze", K::box, 1, 200, 0, {}),
                           row("robust", "disk_rim", K::disk, 1, 100, 9, {}), row("certified", "tri_edge", K::triangle, 1, 500, 0, {}),
                           row("certified", "box_graze", K::box, 1, 200, 0, {})};
  rows[0].promise = Promise{false, Promise::NoFalseMiss::ahead, {}};
  rows[0].stats.promised = 500, rows[0].stats.promise_broken = 2;
  rows[1].promise = Promise{false, Promise::NoFalseMiss::all, {}};
  rows[1].stats.promised = 200;
  for (int i : {3, 4}) rows[static_cast<std::size_t>(i)].promise = exactness(), rows[static_cast<std::size_t>(i)].stats.promised = rows[static_cast<std::size_t>(i)].stats.cases;
  const auto s = report::promise_sentences(rows);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0], "`robust` promises no false miss ahead of the origin (coplanar rays excepted) on triangle: broken on 2 of "
                  "500 cases.");
  EXPECT_EQ(s[1], "`robust` promises no false miss on box: kept on all 200 cases.");
  EXPECT_EQ(s[2], "`certified` promises exact class, t within 1 ulp on triangle, box: kept on all 700 cases.");
  EXPECT_EQ(verify::promise_status(rows[0].stats), "broken on 2 of 500");
  EXPECT_EQ(verify::promise_status(rows[1].stats), "kept on 200");
  EXPECT_EQ(verify::promise_status(rows[2].stats), "none made");
}

TEST(ReportText, NaNAndHugeTErrorsAreExplainedWithAReproducer) {
  Row nan = row("float", "tri_extreme_scale", io::Kind::sphere, 1, 50, 0, {0, kNaN, kNaN}, Precision::float32);
  io::Case big = sphere_case();
  big.v[9] = 1e14;  // a radius whose cube overflows float
  nan.stats.worst = verify::Stats::Worst{kNaN, big, hit(NAN, 2), hit(1, 2)};
  Row far = row("double", "ell_on_surface", io::Kind::sphere, 1, 50, 0, {0, 4500000000000000000ULL});
  far.stats.worst = verify::Stats::Worst{4500000000000000000ULL, sphere_case(), hit(-1e-300, 2), hit(1, 2)};
  Row rel = row("double", "sph_generic", io::Kind::sphere, 1, 50, 0, {0, 2000000000});
  rel.stats.worst = verify::Stats::Worst{2000000000, sphere_case(), hit(4.000001, 6), hit(4, 6)};
  Row small = row("double", "sph_small", io::Kind::sphere, 1, 50, 0, {0, 999999999});
  small.stats.worst = verify::Stats::Worst{999999999, sphere_case(), hit(4.0000001, 6), hit(4, 6)};
  const auto s = report::t_error_sentences({nan, far, rel, small});
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0], "`float` on tri_extreme_scale: the class was right but t was NaN on 2 of 50 cases (in the example a "
                  "coordinate reaches 1e+14: a product of three such overflows float). For example (input as the method "
                  "saw it, its answer, the exact one): `" +
                      io::format_case(big) + "  # got " + io::format_answer(hit(NAN, 2)) + ", exact " +
                      io::format_result(hit(1, 2)) + "`");
  EXPECT_EQ(s[1], "`double` on ell_on_surface: the largest t error is 4.5e+18 double ulps, t on the other side of zero "
                  "(got t = -1e-300, exact t = 1): `" + io::format_case(sphere_case()) + "`");
  EXPECT_EQ(s[2], "`double` on sph_generic: the largest t error is 2e+09 double ulps, a relative error of 2.5e-07 (got t = "
                  "4.000001, exact t = 4): `" + io::format_case(sphere_case()) + "`");
}

TEST(ReportText, TheDefinitionStatesTheTolerance) {
  EXPECT_NE(report::error_free_definition(1).find("else within 1 ulp of its own precision"), std::string::npos);
  EXPECT_NE(report::error_free_definition(8).find("else within 8 ulps of its own precision"), std::string::npos);
}
