/// The exact method against the shared expected files (bit for bit), hand-derived cases, and
/// independent oracles for the rounding: IEEE hardware division and addition (correctly rounded,
/// ties to even, subnormals included) and MPFR at 2000 bits for square roots.
#include "verify/exact_method.h"

#include <gtest/gtest.h>
#include <mpfr.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "io/case_file.h"

#ifndef RAYPROOF_DATA_DIR
#error "RAYPROOF_DATA_DIR must name the directory holding sample.txt and sample.expected"
#endif

namespace rayproof::verify {
namespace {

using io::CaseResult;
using io::Kind;
constexpr auto kNone = std::nullopt;

io::Case make_case(Kind kind, std::vector<double> v) {
  io::Case c;
  c.kind = kind;
  for (std::size_t i = 0; i < v.size(); ++i) c.v[i] = v[i];
  return c;
}

/// Equal as doubles including the sign of zero (and NaN never appears).
void expect_same(const CaseResult& got, const CaseResult& want, const std::string& what) {
  EXPECT_EQ(io::format_result(got), io::format_result(want)) << what;
  for (auto [g, w] : {std::pair{got.t, want.t}, std::pair{got.t2, want.t2}})
    if (g && w) {
      EXPECT_EQ(std::signbit(*g), std::signbit(*w)) << what;
    }
}

void check_file(const std::string& stem) {
  const std::string dir = RAYPROOF_DATA_DIR;
  std::ifstream cases(dir + "/" + stem + ".txt"), expected(dir + "/" + stem + ".expected");
  ASSERT_TRUE(cases && expected) << dir << "/" << stem;
  const auto entries = io::read_cases(cases);
  std::vector<std::string> want;
  for (std::string line; std::getline(expected, line);)
    if (!line.empty()) want.push_back(line);
  ASSERT_EQ(entries.size(), want.size());
  std::size_t matched = 0;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const auto* c = std::get_if<io::Case>(&entries[i]);
    ASSERT_NE(c, nullptr) << "case file line " << i;
    const std::string got = io::format_result(exact_classify(*c));
    EXPECT_EQ(got, want[i]) << stem << ".txt line " << c->line << ": " << io::format_case(*c);
    matched += got == want[i];
  }
  EXPECT_EQ(matched, want.size());
}

TEST(ExactFiles, SampleBitForBit) { check_file("sample"); }
TEST(ExactFiles, WorkedExamplesBitForBit) { check_file("worked_examples"); }

TEST(ExactTriangle, HandDerived) {
  // The ray (0,0,0) + t(1,1,1) passes through the vertex (2,2,2) at t = 2 ...
  expect_same(exact_classify(make_case(Kind::triangle, {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 7, -1, 0, 9, -4})),
              {Contact::vertex, 2.0, kNone}, "vertex at t=2");
  // ... and starts on the vertex (0,0,0): a hit at t = 0 prints +0.0.
  expect_same(exact_classify(make_case(Kind::triangle, {0, 0, 0, 1, 1, 1, 0, 0, 0, 3, 7, -1, 0, 9, -4})),
              {Contact::vertex, 0.0, kNone}, "vertex at t=0");
  // In the plane z = 1 along the edge (3,3,1)-(7,7,1): touches the closed triangle for t in [3, 7].
  expect_same(exact_classify(make_case(Kind::triangle, {0, 0, 1, 1, 1, 0, 3, 3, 1, 7, 7, 1, 0, -9, -4})),
              {Contact::coplanar, 3.0, 7.0}, "coplanar along an edge");
  // In the plane but pointing away: `- -`.
  expect_same(exact_classify(make_case(Kind::triangle, {0, 0, 1, -1, -1, 0, 3, 3, 1, 7, 7, 1, 0, -9, -4})),
              {Contact::coplanar, kNone, kNone}, "coplanar, away");
  // Origin inside the triangle, in its plane: range starts at 0.
  expect_same(exact_classify(make_case(Kind::triangle, {0, 0, 0, 1, 0, 0, -1, -1, 0, 3, -1, 0, -1, 3, 0})),
              {Contact::coplanar, 0.0, 2.0}, "coplanar from inside");
  // Through a single corner in the plane: T = T2.
  expect_same(exact_classify(make_case(Kind::triangle, {-1, 1, 0, 1, -1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0})),
              {Contact::coplanar, 1.0, 1.0}, "coplanar, touching a vertex");
  expect_same(exact_classify(make_case(Kind::triangle, {0, 0, 1, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0})),
              {Contact::parallel, kNone, kNone}, "parallel");
  expect_same(exact_classify(make_case(Kind::triangle, {0, 0, 0, 0, 0, 1, 0, 0, 5, 1, 1, 5, 2, 2, 5})),
              {Contact::degenerate, kNone, kNone}, "collinear");
  expect_same(exact_classify(make_case(Kind::triangle, {5, 5, 0, 0, 0, 1, 0, 0, 5, 1, 0, 5, 0, 1, 5})),
              {Contact::miss, kNone, kNone}, "miss");
}

TEST(ExactQuadric, WorkedEllipsoidMatchesMpfr) {
  // t = 2 -+ sqrt(4/5), computed here directly at 2000 bits and rounded once.
  mpfr_t s, x;
  mpfr_inits2(2000, s, x, static_cast<mpfr_ptr>(nullptr));
  mpfr_set_ui(s, 4, MPFR_RNDN);
  mpfr_div_ui(s, s, 5, MPFR_RNDN);
  mpfr_sqrt(s, s, MPFR_RNDN);
  mpfr_ui_sub(x, 2, s, MPFR_RNDN);
  const double lower = mpfr_get_d(x, MPFR_RNDN);
  mpfr_add_ui(x, s, 2, MPFR_RNDN);
  const double upper = mpfr_get_d(x, MPFR_RNDN);
  mpfr_clears(s, x, static_cast<mpfr_ptr>(nullptr));
  expect_same(exact_classify(make_case(Kind::ellipsoid, {0, 0, 0, 1, 1, 0, 2, 2, 0, 2, 1, 2})),
              {Contact::hit, lower, upper}, "2 -+ sqrt(4/5)");
  EXPECT_EQ(lower, 1.105572809000084);
  EXPECT_EQ(upper, 2.8944271909999157);
}

TEST(ExactQuadric, ExactTiesRoundToEven) {
  const double h = std::ldexp(1.0, -53), u = std::ldexp(1.0, -52);
  // Roots 1 -+ 2^-53: 1 - 2^-53 is a double; 1 + 2^-53 is the midpoint of 1 and 1 + 2^-52 -> 1.
  expect_same(exact_classify(make_case(Kind::sphere, {0, 0, 0, 1, 0, 0, 1, 0, 0, h})),
              {Contact::hit, 1.0 - h, 1.0}, "tie down to even");
  // Roots 1 + 2^-52 -+ 2^-53: both midpoints; to even: 1 and 1 + 2^-51.
  expect_same(exact_classify(make_case(Kind::sphere, {0, 0, 0, 1, 0, 0, 1 + u, 0, 0, h})),
              {Contact::hit, 1.0, 1.0 + 2 * u}, "ties both ways");
  // Same roots through a non-unit direction (a = 4, b = -2(1+u)).
  expect_same(exact_classify(make_case(Kind::sphere, {0, 0, 0, 0.5, 0, 0, 0.5 + u / 2, 0, 0, h / 2})),
              {Contact::hit, 1.0, 1.0 + 2 * u}, "ties, scaled direction");
  // Rational ties (plane): t = 1 + 2^-53 -> 1 and t = 1 + 3 * 2^-53 -> 1 + 2^-51.
  expect_same(exact_classify(make_case(Kind::plane, {-h, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0})),
              {Contact::hit, 1.0, kNone}, "rational tie down");
  expect_same(exact_classify(make_case(Kind::plane, {-3 * h, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0})),
              {Contact::hit, 1.0 + 2 * u, kNone}, "rational tie up");
  // Subnormal ties: 2^-1075 -> 0, 3 * 2^-1075 -> 2^-1073.
  const double tiny = std::numeric_limits<double>::denorm_min();
  expect_same(exact_classify(make_case(Kind::plane, {0, 0, 0, 2, 0, 0, tiny, 0, 0, 1, 0, 0})),
              {Contact::hit, 0.0, kNone}, "subnormal tie to zero");
  expect_same(exact_classify(make_case(Kind::plane, {0, 0, 0, 2, 0, 0, 3 * tiny, 0, 0, 1, 0, 0})),
              {Contact::hit, 2 * tiny, kNone}, "subnormal tie up");
}

TEST(ExactQuadric, ZeroRoots) {
  // Origin on the sphere heading out: inside, T2 = -0.0 (the reference's c / k with k < 0).
  expect_same(exact_classify(make_case(Kind::sphere, {1, 0, 0, 1, 0, 0, 0, 0, 0, 1})),
              {Contact::inside, -2.0, -0.0}, "on surface, heading out");
  expect_same(exact_classify(make_case(Kind::sphere, {1, 0, 0, -1, 0, 0, 0, 0, 0, 1})),
              {Contact::hit, 0.0, 2.0}, "on surface, heading in");
  expect_same(exact_classify(make_case(Kind::sphere, {0, 1, 0, 1, 0, 0, 0, 0, 0, 1})),
              {Contact::tangent, 0.0, 0.0}, "tangent at 0");
  expect_same(exact_classify(make_case(Kind::sphere, {0, 1, 0, 1, 0, 0, -3, 0, 0, 1})),
              {Contact::behind, -3.0, -3.0}, "tangent behind");
  expect_same(exact_classify(make_case(Kind::sphere, {0, 0, 0, 1, 0, 0, -5, 0, 0, 1})),
              {Contact::behind, -6.0, -4.0}, "behind");
  expect_same(exact_classify(make_case(Kind::sphere, {0, 2, 0, 1, 0, 0, 5, 0, 0, 1})),
              {Contact::miss, kNone, kNone}, "miss");
}

/// Sign-exact oracle for a ray with d = (dx, 0, 0) from (0, y, 0) against a sphere at (cx, 0, 0):
/// roots (cx -+ sqrt(r^2 - y^2)) / dx, evaluated at 2000 bits and rounded once.
std::pair<double, double> mpfr_roots(double dx, double y, double cx, double r) {
  mpfr_t s, t, x;
  mpfr_inits2(2000, s, t, x, static_cast<mpfr_ptr>(nullptr));
  mpfr_set_d(s, r, MPFR_RNDN);
  mpfr_sqr(s, s, MPFR_RNDN);
  mpfr_set_d(t, y, MPFR_RNDN);
  mpfr_sqr(t, t, MPFR_RNDN);
  mpfr_sub(s, s, t, MPFR_RNDN);  // exact: 106-bit products of close magnitude
  mpfr_sqrt(s, s, MPFR_RNDN);
  std::pair<double, double> out;
  for (int k : {-1, 1}) {
    mpfr_set_d(x, cx, MPFR_RNDN);
    if (k < 0) mpfr_sub(x, x, s, MPFR_RNDN);
    else mpfr_add(x, x, s, MPFR_RNDN);
    mpfr_div_d(x, x, dx, MPFR_RNDN);
    (k < 0 ? (dx > 0 ? out.first : out.second) : (dx > 0 ? out.second : out.first)) = mpfr_get_d(x, MPFR_RNDN);
  }
  mpfr_clears(s, t, x, static_cast<mpfr_ptr>(nullptr));
  return out;
}

TEST(ExactQuadric, IrrationalRootsMatchMpfr) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked = 0;
  for (int i = 0; i < 3000; ++i) {
    const double dx = std::ldexp(unit(rng), static_cast<int>(rng() % 21) - 10);
    const double y = unit(rng), cx = 8 * unit(rng), r = std::abs(unit(rng)) + 0.001;
    if (dx == 0 || std::abs(y) >= r) continue;
    const CaseResult got = exact_classify(make_case(Kind::sphere, {0, y, 0, dx, 0, 0, cx, 0, 0, r}));
    const auto [lo, hi] = mpfr_roots(dx, y, cx, r);
    ASSERT_TRUE(got.t && got.t2) << i;
    EXPECT_EQ(*got.t, lo) << i;
    EXPECT_EQ(*got.t2, hi) << i;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(ExactQuadric, RationalRootsMatchHardwareAddition) {
  // d = (1,0,0) from the origin, center (cx,0,0): roots cx -+ r, which IEEE addition rounds
  // correctly (ties to even), including near-tie radii of half an ulp of cx.
  std::mt19937_64 rng(777);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int i = 0; i < 3000; ++i) {
    const double cx = std::ldexp(unit(rng), static_cast<int>(rng() % 200) - 100);
    double r = std::abs(std::ldexp(unit(rng), static_cast<int>(rng() % 200) - 100));
    const double ulp = std::nextafter(std::abs(cx), 1e300) - std::abs(cx);
    if (i % 3 == 0) r = ulp / 2 * (1 + static_cast<int>(rng() % 5));  // exact ties and neighbours
    if (r == 0 || std::abs(cx) == r) continue;
    const CaseResult got = exact_classify(make_case(Kind::sphere, {0, 0, 0, 1, 0, 0, cx, 0, 0, r}));
    ASSERT_TRUE(got.t && got.t2) << i;
    EXPECT_EQ(*got.t, cx - r) << i << " cx=" << cx << " r=" << r;
    EXPECT_EQ(*got.t2, cx + r) << i << " cx=" << cx << " r=" << r;
  }
}

TEST(ExactPlane, RationalTMatchesHardwareDivision) {
  // t = px / dx exactly; IEEE division is correctly rounded, subnormal and overflowing results too.
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const double px = std::ldexp(unit(rng), static_cast<int>(rng() % 2098) - 1074);
    const double dx = std::ldexp(unit(rng), static_cast<int>(rng() % 2098) - 1074);
    if (px == 0 || dx == 0) continue;
    const CaseResult got = exact_classify(make_case(Kind::plane, {0, 0, 0, dx, 0, 0, px, 0, 0, 1, 0, 0}));
    const double want = px / dx;
    ASSERT_TRUE(got.t) << i;
    EXPECT_EQ(io::format_double(*got.t), io::format_double(want)) << "px=" << px << " dx=" << dx;
    EXPECT_EQ(got.contact, (px > 0) == (dx > 0) ? Contact::hit : Contact::behind);
  }
}

TEST(ExactScreening, InvalidBeforeDegenerate) {
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  const CaseResult invalid{Contact::invalid, kNone, kNone}, degenerate{Contact::degenerate, kNone, kNone};
  expect_same(exact_classify(make_case(Kind::sphere, {0, 0, 0, nan, 0, 1, 0, 0, 5, 0})), invalid, "NaN, zero r");
  expect_same(exact_classify(make_case(Kind::plane, {0, 0, 0, 1, 0, 0, inf, 0, 0, 0, 0, 0})), invalid, "inf");
  expect_same(exact_classify(make_case(Kind::triangle, {0, 0, 0, 0, 0, -0.0, 0, 0, 1, 0, 0, 1, 0, 0, 1})), invalid,
              "d = 0 with a collinear triangle");
  expect_same(exact_classify(make_case(Kind::sphere, {0, 0, -5, 0, 0, 1, 0, 0, 0, -1})), invalid, "negative r");
  expect_same(exact_classify(make_case(Kind::ellipsoid, {0, 0, 0, 1, 0, 0, 0, 0, 0, 1, -1, 0})), invalid, "axis");
  expect_same(exact_classify(make_case(Kind::box, {0, 0, 0, 1, 1, 1, 1, 1, 1, 0, 2, 2})), invalid, "lo > hi");
  expect_same(exact_classify(make_case(Kind::disk, {0, 0, 0, 0, 0, 1, 0, 0, 5, 0, 0, 0, -2})), invalid, "disk r");
  expect_same(exact_classify(make_case(Kind::plane, {0, 0, 0, 1, 0, 0, 5, 0, 0, 0, -0.0, 0})), degenerate, "normal");
  expect_same(exact_classify(make_case(Kind::disk, {0, 0, 0, 0, 0, 1, 0, 0, 5, 0, 0, 1, 0})), degenerate, "disk r");
  expect_same(exact_classify(make_case(Kind::ellipsoid, {0, 0, 0, 1, 0, 0, 5, 0, 0, 1, 0, 1})), degenerate, "axis");
  expect_same(exact_classify(make_case(Kind::sphere, {0, 0, 0, 1, 0, 0, 5, 0, 0, -0.0})), degenerate, "r = -0");
  // A flat box (lo = hi on z) is classified as usual.
  expect_same(exact_classify(make_case(Kind::box, {0, 0, -1, 0, 0, 1, -1, -1, 0, 1, 1, 0})),
              {Contact::graze, 1.0, 1.0}, "flat box");
}

TEST(ExactBoxDisk, HandDerived) {
  expect_same(exact_classify(make_case(Kind::box, {-3, 4, 5, 1, -1, -2, -2, -2, -2, 2, 2, 2})),
              {Contact::hit, 2.0, 3.5}, "worked box");
  expect_same(exact_classify(make_case(Kind::box, {0, 0, 0, 1, 0, 0, -1, 1, -1, 1, 2, 1})),
              {Contact::miss, kNone, kNone}, "d_y = 0 outside the slab");
  expect_same(exact_classify(make_case(Kind::box, {0, 0, 0, 1, 1, 0, 1, -1, -1, 2, 1, 1})),
              {Contact::graze, 1.0, 1.0}, "through an edge");
  expect_same(exact_classify(make_case(Kind::box, {0, 0, 0, 1, 0, 0, -1, -1, -1, 0, 1, 1})),
              {Contact::inside, -1.0, 0.0}, "origin on the exit face");
  expect_same(exact_classify(make_case(Kind::disk, {3, 4, 5, 0, 0, -1, 0, 0, 0, 0, 0, 1, 5})),
              {Contact::rim, 5.0, kNone}, "rim: 3-4-5");
  expect_same(exact_classify(make_case(Kind::disk, {3, 4, -5, 0, 0, -1, 0, 0, 0, 0, 0, 1, 5})),
              {Contact::behind, -5.0, kNone}, "rim behind is behind");
  expect_same(exact_classify(make_case(Kind::disk, {3, 4.5, 5, 0, 0, -1, 0, 0, 0, 0, 0, 1, 5})),
              {Contact::miss, kNone, kNone}, "just outside");
  expect_same(exact_classify(make_case(Kind::disk, {3, 4, 0, 1, 0, 0, 0, 0, 0, 0, 0, 1, 5})),
              {Contact::coplanar, kNone, kNone}, "coplanar");
}

TEST(ExactExtremes, HugeAndSubnormalInputsDoNotCrash) {
  const double big = 1e300, huge = std::numeric_limits<double>::max(), tiny = 4.9e-324, sub = 1e-310;
  // Origin on a huge sphere heading in, with a tiny direction: T2 = 2e600 overflows to inf.
  expect_same(exact_classify(make_case(Kind::sphere, {-big, 0, 0, 1e-300, 0, 0, 0, 0, 0, big})),
              {Contact::hit, 0.0, std::numeric_limits<double>::infinity()}, "overflowing root");
  expect_same(exact_classify(make_case(Kind::plane, {0, 0, 0, tiny, 0, 0, huge, 0, 0, huge, 0, 0})),
              {Contact::hit, std::numeric_limits<double>::infinity(), kNone}, "overflowing t");
  expect_same(exact_classify(make_case(Kind::plane, {0, 0, 0, huge, 0, 0, tiny, 0, 0, tiny, tiny, 0})),
              {Contact::hit, 0.0, kNone}, "underflowing t");
  expect_same(exact_classify(make_case(Kind::box, {0, 0, 0, 1, 1, 1, sub, sub, sub, 2 * sub, 2 * sub, 2 * sub})),
              {Contact::hit, sub, 2 * sub}, "subnormal box");
  expect_same(exact_classify(make_case(Kind::sphere, {0, 0, 0, 1, 0, 0, 2 * sub, 0, 0, sub})),
              {Contact::hit, sub, 3 * sub}, "subnormal sphere");
  // Irrational roots -+ sqrt(3/4) / dx: overflowing to -+inf, and subnormal.
  const double inf = std::numeric_limits<double>::infinity();
  expect_same(exact_classify(make_case(Kind::sphere, {0, 0.5, 0, tiny, 0, 0, 0, 0, 0, 1})),
              {Contact::inside, -inf, inf}, "overflowing irrational roots");
  const auto [lo, hi] = mpfr_roots(huge, 0.5, 0, 1);
  EXPECT_TRUE(std::fpclassify(hi) == FP_SUBNORMAL) << hi;
  expect_same(exact_classify(make_case(Kind::sphere, {0, 0.5, 0, huge, 0, 0, 0, 0, 0, 1})),
              {Contact::inside, lo, hi}, "subnormal irrational roots");
  const std::vector<double> scales = {1e-320, 1e-300, 1e-150, 1, 1e150, 1e300, huge};
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (Kind kind : io::kAllKinds) {
    for (int i = 0; i < 200; ++i) {
      io::Case c;
      c.kind = kind;
      for (int f = 0; f < io::field_count(kind); ++f) c.v[static_cast<std::size_t>(f)] = unit(rng) * scales[rng() % scales.size()];
      const CaseResult r = exact_classify(c);
      EXPECT_NE(r.contact, Contact::error) << io::format_case(c);
      if (r.t) {
        EXPECT_FALSE(std::isnan(*r.t)) << io::format_case(c);
      }
      if (r.t && r.t2) {
        EXPECT_LE(*r.t, *r.t2) << io::format_case(c);
      }
    }
  }
}

TEST(ExactMethod, RegisteredForEveryKind) {
  MethodRegistry reg;
  register_exact_method(reg);
  const Method* m = reg.find("exact");
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->precision, Precision::float64);
  for (Kind k : io::kAllKinds) EXPECT_TRUE(m->supports(k));
  expect_same(m->run(make_case(Kind::sphere, {0, 0, 0, 1, 0, 0, 5, 0, 0, 1})), {Contact::hit, 4.0, 6.0}, "run");
}

}  // namespace
}  // namespace rayproof::verify
