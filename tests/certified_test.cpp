/// The certified method against the exact one: same class on every case, T and T2 within one
/// double ulp, on data/sample.txt and on every generator family; plus worked examples per kind.
#include "verify/certified_method.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "gen/families.h"
#include "io/case_file.h"
#include "methods/method.h"
#include "rayproof/certified_box.h"
#include "rayproof/certified_fma.h"
#include "rayproof/certified_stage.h"
#include "rayproof/certified_triangle.h"
#include "verify/differential.h"
#include "verify/exact_method.h"

using namespace rayproof;

namespace {

io::Case parse(const std::string& line) {
  std::string family;
  const auto e = io::parse_case_line(line, 1, family);
  return std::get<io::Case>(*e);
}

/// Empty when certified agrees with exact on c; else a description.
std::string disagreement(const io::Case& c) {
  const io::CaseResult got = verify::certified_classify(c), want = verify::exact_classify(c);
  if (got.contact == want.contact && verify::t_error_ulps(got, want, Precision::float64) <= 1) return {};
  return io::format_case(c) + " got " + io::format_result(got) + " want " + io::format_result(want);
}

}  // namespace

TEST(Certified, WorkedExamples) {
  auto run = [](const std::string& s) { return io::format_result(verify::certified_classify(parse(s))); };
  EXPECT_EQ(run("ellipsoid 0 0 0 1 1 0 2 2 0 2 1 2"), "hit 1.105572809000084 2.8944271909999157");
  EXPECT_EQ(run("box -3 4 5 1 -1 -2 -2 -2 -2 2 2 2"), "hit 2.0 3.5");
  EXPECT_EQ(run("triangle 0 0 0 1 1 1 2 2 2 3 7 -1 0 9 -4"), "vertex 2.0 -");
  EXPECT_EQ(run("triangle 0 0 1 1 1 0 3 3 1 7 7 1 0 -9 -4"), "coplanar 3.0 7.0");
  EXPECT_EQ(run("plane 0 0 0 1 1 0 0 0 5 0 0 1"), "parallel - -");
  EXPECT_EQ(run("sphere 0 0 0 0 0 1 0 0 5 1"), "hit 4.0 6.0");
  EXPECT_EQ(run("disk 0 0 0 0 0 1 0 0 5 0 0 1 2"), "hit 5.0 -");
  EXPECT_EQ(run("sphere 0 0 0 0 0 1 0 0 5 nan"), "invalid - -");
}

/// The double-double path runs whenever the CPU has FMA, and RAYPROOF_CERTIFIED_NO_FMA turns it off
/// (ctest runs this suite both ways: certified_test and certified_test_x87).
TEST(Certified, FmaPathFollowsCpuAndEnvironment) {
  const bool off = std::getenv("RAYPROOF_CERTIFIED_NO_FMA") != nullptr;
#if RAYPROOF_FMA_PATH == 2
  const bool cpu = __builtin_cpu_supports("fma") != 0 && __builtin_cpu_supports("avx2") != 0;
#else
  const bool cpu = RAYPROOF_FMA_PATH == 1;
#endif
  EXPECT_EQ(certified::dd::available(), cpu && !off);
}

TEST(Certified, FilterDecidesGenericCasesWithoutFallback) {
  for (const char* s : {"triangle 0.1 0.2 0 0.3 0.1 1 -1 -1 3 1 -1 3 0 1 3", "sphere 0.1 0 0 0.2 0.3 1 0 0 5 1.5",
                        "box -3 4 5 1 -1 -2 -2 -2 -2 2 2 2", "plane 0.1 0 0 1 1 3 0 0 5 0.1 0.2 1"}) {
    EXPECT_TRUE(verify::certified_filter(parse(s)).has_value()) << s;
  }
}

TEST(Certified, EqualsExactOnEverySampleLine) {
  std::ifstream in(std::string(RAYPROOF_DATA_DIR) + "/sample.txt");
  std::ifstream expected(std::string(RAYPROOF_DATA_DIR) + "/sample.expected");
  ASSERT_TRUE(in && expected);
  std::size_t n = 0;
  std::string want_line;
  for (const auto& e : io::read_cases(in)) {
    ASSERT_TRUE(std::getline(expected, want_line));
    const auto* c = std::get_if<io::Case>(&e);
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(disagreement(*c), "");
    const auto want = io::parse_result(want_line);
    ASSERT_TRUE(want.has_value()) << want_line;
    EXPECT_EQ(verify::certified_classify(*c).contact, want->contact) << io::format_case(*c);
    ++n;
  }
  EXPECT_EQ(n, 602u);
}

/// 6,000 cases of every family (~190k), double and float precision: no disagreement.
TEST(Certified, EqualsExactOnEveryGeneratedFamily) {
  std::size_t cases = 0, fallbacks = 0, bad = 0;
  for (const auto& f : gen::families()) {
    for (auto p : {gen::Precision::float64, gen::Precision::float32}) {
      for (const io::Case& c : gen::generate(f, 3000, 11, p)) {
        std::uint64_t fb = 0;
        const io::CaseResult got = verify::certified_classify(c, &fb), want = verify::exact_classify(c);
        fallbacks += fb;
        ++cases;
        if (got.contact != want.contact || verify::t_error_ulps(got, want, Precision::float64) > 1) {
          if (++bad <= 10) ADD_FAILURE() << f.name << ": " << io::format_case(c) << " got " << io::format_result(got)
                                         << " want " << io::format_result(want);
        }
      }
    }
  }
  EXPECT_EQ(bad, 0u);
  EXPECT_GE(cases, 190000u);
  std::printf("certified: %zu cases, %zu fallbacks (%.1f%%)\n", cases, fallbacks, 100.0 * double(fallbacks) / double(cases));
}

// ---- The staged filters: exact contacts proven without the GMP fallback ----

namespace {

/// A sphere case from its ray and sphere.
io::Case sphere_case(const Vec3<double>& o, const Vec3<double>& d, const Vec3<double>& c, double r) {
  return {io::Kind::sphere, {o.x, o.y, o.z, d.x, d.y, d.z, c.x, c.y, c.z, r}, {}, 0};
}

/// Counts the cases the filter leaves to GMP, and checks every answer against exact.
struct Tally {
  std::size_t cases = 0, fallbacks = 0, bad = 0;
  void run(const io::Case& c) {
    std::uint64_t fb = 0;
    const io::CaseResult got = verify::certified_classify(c, &fb), want = verify::exact_classify(c);
    ++cases;
    fallbacks += fb;
    if (got.contact != want.contact || verify::t_error_ulps(got, want, Precision::float64) > 1) {
      if (++bad <= 5) ADD_FAILURE() << io::format_case(c) << " got " << io::format_result(got) << " want " << io::format_result(want);
    }
  }
};

}  // namespace

/// Edges, vertices, behind contacts through them, tangents, origins on quadrics, rims and grazes built
/// from small integers: all exact zeros, decided by the expansion stage (no fallback).
TEST(Certified, ExactContactsNeedNoFallback) {
  std::mt19937_64 g(3);
  std::uniform_int_distribution<int> I(-20, 20);
  Tally t;
  char buf[512];
  for (int i = 0; i < 3000; ++i) {
    // Triangle with integer vertices; a ray from an integer origin through an edge midpoint or a vertex.
    int p[9];
    for (int& x : p) x = I(g);
    const int o[3] = {I(g) + 50, I(g), I(g)};
    const int k = i % 3, j = (k + 1) % 3;
    double target[3];
    for (int a = 0; a < 3; ++a) target[a] = i % 2 ? p[3 * k + a] : 0.5 * (p[3 * k + a] + p[3 * j + a]);
    const double s = i % 4 < 2 ? 1.0 : -1.0;  // -1: the contact is behind the origin
    std::snprintf(buf, sizeof buf, "triangle %d %d %d %.17g %.17g %.17g %d %d %d %d %d %d %d %d %d", o[0], o[1], o[2],
                  s * (target[0] - o[0]), s * (target[1] - o[1]), s * (target[2] - o[2]), p[0], p[1], p[2], p[3], p[4], p[5],
                  p[6], p[7], p[8]);
    t.run(parse(buf));
  }
  // Tangents (3-4-5 triangles scaled), origins on the surface, rims, box corners and edges.
  for (int i = 1; i <= 200; ++i) {
    const int c = i % 7 - 3;
    std::snprintf(buf, sizeof buf, "sphere %d -10 %d 0 1 0 %d 0 %d %d", c + 3 * i, c, c, c, 3 * i);  // tangent at x = c + 3i
    t.run(parse(buf));
    std::snprintf(buf, sizeof buf, "sphere %d %d 0 %d 1 %d 0 0 0 %d", 3 * i, 4 * i, -i, i % 5, 5 * i);  // origin on it
    t.run(parse(buf));
    std::snprintf(buf, sizeof buf, "ellipsoid %d %d 0 0 0 1 0 0 0 %d %d %d", 2 * i, 0, 2 * i, 3, 1 + i % 4);  // on it
    t.run(parse(buf));
    std::snprintf(buf, sizeof buf, "disk %d %d 7 0 0 -1 0 0 0 0 0 1 %d", 3 * i, 4 * i, 5 * i);  // rim
    t.run(parse(buf));
    std::snprintf(buf, sizeof buf, "box %d %d %d 1 1 1 0 0 0 %d %d %d", -i, -i, -i, i, i, i);  // corner graze at t = i
    t.run(parse(buf));
    std::snprintf(buf, sizeof buf, "box %d 0 %d 1 1 0 0 %d 0 %d %d %d", -i, -i, -i, i, i, i);  // on a face: hit
    t.run(parse(buf));
    std::snprintf(buf, sizeof buf, "plane %d %d %d 1 2 3 %d %d %d 1 2 3", i, -i, 2 * i, i, -i, 2 * i);  // origin on plane
    t.run(parse(buf));
  }
  EXPECT_EQ(t.bad, 0u);
  EXPECT_EQ(t.fallbacks, 0u) << "of " << t.cases;
}

/// Boxes: rays through corners, edge points and face points, and origins on faces, built from small
/// integers scaled by 2^k (k in [-60, 60], so every b - o is exact and the slab distances tie or touch
/// exactly), plus the same with one coordinate moved by an ulp (ties that round alike but are not
/// exact). Stage 1's tie step (box_tie, exact fraction comparisons) decides the exact ones: no fallback.
TEST(Certified, BoxTiesGrazesAndFaceStartsAtEveryScale) {
  std::mt19937_64 g(41);
  std::uniform_int_distribution<int> I(-20, 20), K(-60, 60), P(0, 2);
  Tally exact_ties, perturbed;
  for (int i = 0; i < 20000; ++i) {
    const double s = std::ldexp(1.0, K(g));
    io::Case c{io::Kind::box, {}, {}, 0};
    double lo[3], hi[3], o[3], target[3];
    for (int a = 0; a < 3; ++a) {
      const int x = I(g), w = 1 + std::abs(I(g)) / 2;
      lo[a] = s * x, hi[a] = s * (x + w), o[a] = s * (I(g) * 3);
      const int pick = P(g);  // the target on lo, on hi, or at the middle of the slab
      target[a] = pick == 0 ? lo[a] : (pick == 1 ? hi[a] : 0.5 * (lo[a] + hi[a]));
    }
    if (i % 5 == 0) {  // origin on a face plane
      // Not `(i % 2 ? lo : hi)[f]`: GCC 12 under -fsanitize=undefined evaluates the index's saved
      // operand in one arm of that conditional only, and the other arm reads it uninitialized (wrong
      // faces, and "index -2 out of bounds" when the stack held a negative value). See
      // tests/lint/conditional_subscript.sh.
      const int f = i % 3;
      o[f] = i % 2 ? lo[f] : hi[f];
    }
    bool zero = true;
    for (int a = 0; a < 3; ++a) {
      const double sign = i % 7 == 0 ? -1.0 : 1.0;  // some rays point away: behind
      c.v[a] = o[a], c.v[3 + a] = sign * (target[a] - o[a]), c.v[6 + a] = lo[a], c.v[9 + a] = hi[a];
      zero = zero && c.v[3 + a] == 0;
    }
    if (zero) continue;
    exact_ties.run(c);
    io::Case p = c;
    const std::size_t f = g() % 12;
    p.v[f] = (g() & 1) ? certified::next_above(p.v[f]) : certified::next_below(p.v[f]);
    perturbed.run(p);
  }
  EXPECT_EQ(exact_ties.bad, 0u);
  EXPECT_EQ(perturbed.bad, 0u);
  EXPECT_EQ(exact_ties.fallbacks, 0u) << "of " << exact_ties.cases;
  std::printf("box ties: %zu exact cases, %zu perturbed (%zu fallbacks)\n", exact_ties.cases, perturbed.cases,
              perturbed.fallbacks);
}

/// frac_cmp (the box's exact comparison of slab distances p1 / d1 and p2 / d2) against 128-bit integer
/// arithmetic, on integers below 2^53 whose quotients lie within a few ulps of each other, so the
/// rounded products are often equal and the fma error terms decide. Then the same fractions as the
/// entry and the exit of box rays (o = 0: entry p1 / d1 through x = lo_x, exit p2 / d2 through
/// y = hi_y), against the exact method.
TEST(Certified, BoxFractionComparisonIsExact) {
  std::mt19937_64 g(43);
  std::uniform_int_distribution<std::int64_t> B(std::int64_t(1) << 40, (std::int64_t(1) << 53) - 1);
  std::size_t equal_products = 0, cases = 0;
  Tally box;
  for (int i = 0; i < 20000; ++i) {
    const std::int64_t p1 = B(g), d1 = B(g), d2 = B(g);
    const std::int64_t k = static_cast<std::int64_t>(g() % 5) - 2;
    const double q = std::nearbyint(double(p1) / double(d1) * double(d2));
    if (!(q < 0x1p53 - 2)) continue;  // p2 would not be exact as a double (and the cast must stay in range)
    const std::int64_t p2 = static_cast<std::int64_t>(q) + k;
    const __int128 x = __int128(p1) * d2, y = __int128(p2) * d1;
    const int want = x > y ? 1 : (x < y ? -1 : 0);
    const auto got = certified::detail::frac_cmp(double(p1), double(d1), double(p2), double(d2));
    ASSERT_TRUE(got.has_value());
    ASSERT_EQ(*got, want) << p1 << "/" << d1 << " vs " << p2 << "/" << d2;
    const auto flipped = certified::detail::frac_cmp(-double(p1), -double(d1), double(p2), double(d2));
    ASSERT_EQ(flipped.value_or(9), want);  // the same fraction with both signs flipped
    equal_products += double(p1) * double(d2) == double(p2) * double(d1);
    ++cases;
    const double big = 0x1p60;
    box.run({io::Kind::box, {0, 0, 0, double(d1), double(d2), 1, double(p1), -big, -big, big, double(p2), big}, {}, 0});
  }
  EXPECT_GT(equal_products, cases / 20);  // the error terms were exercised (~9% of cases)
  EXPECT_EQ(box.bad, 0u);
  EXPECT_EQ(box.fallbacks, 0u) << "of " << box.cases;
}

/// Near-degenerate inputs: contacts perturbed by one ulp in one coordinate, every kind. The filter
/// may fall back, but never disagrees with exact.
TEST(Certified, AgreesWithExactOnNearDegenerateInputs) {
  std::mt19937_64 g(17);
  Tally t;
  for (const auto& f : gen::families()) {
    for (io::Case c : gen::generate(f, 400, 5, gen::Precision::float64)) {
      for (int r = 0; r < 3; ++r) {
        io::Case p = c;
        const std::size_t i = g() % static_cast<std::size_t>(io::field_count(c.kind));
        p.v[i] = (g() & 1) ? certified::next_above(p.v[i]) : certified::next_below(p.v[i]);
        if (std::isfinite(p.v[i])) t.run(p);
      }
    }
  }
  EXPECT_EQ(t.bad, 0u);
  std::printf("near-degenerate: %zu cases, %zu fallbacks\n", t.cases, t.fallbacks);
}

/// Regression (fuzz_kernels, data/regressions/certified.txt): subnormal coordinates beside -5.5e303.
/// A product in the double running-error stage underflowed to v = 0 with radius eta; the next
/// product's radius |d.z| eta flushed to 0 as well, so u1 looked like an exact zero ("edge" for a
/// miss). Every product / quotient of operands not exactly zero now adds an underflow term.
TEST(Certified, RunningErrorRadiusUnderflow) {
  using B = certified::BoundedT<double>;
  const B x(0x1p-600);
  const B z = x * x;  // underflows: v = 0, r > 0
  EXPECT_EQ(z.v, 0.0);
  EXPECT_GT(z.r, 0.0);
  EXPECT_FALSE(certified::sign(z).has_value());
  EXPECT_FALSE(certified::sign(z * B(0x1p-600)).has_value());  // radius must not flush to 0 either
  EXPECT_FALSE(certified::sign(B(0x1p-600) * z).has_value());
  EXPECT_FALSE(certified::sign(z / B(0x1p+600)).has_value());
  EXPECT_EQ(certified::sign(B(0.0) * z), 0);  // an exact zero factor stays exact
}

TEST(Certified, AgreesWithExactOnSubnormalsBesideHugeCoordinates) {
  const double base[15] = {1.69759663277e-313, 2.238042436e-315, 0.0,
                           1.393066875581823e-309, 9.74564754702648e-309, 2.8480945388894844e-305,
                           1.390650356385185e-309, 0.0, 0.0,
                           0.0, -5.486124068813628e+303, 0.0,
                           0.0, 0.0, 0.0};
  EXPECT_EQ(disagreement(parse("triangle 1.69759663277e-313 2.238042436e-315 0.0 1.393066875581823e-309 "
                               "9.74564754702648e-309 2.8480945388894844e-305 1.390650356385185e-309 0.0 0.0 "
                               "0.0 -5.486124068813628e+303 0.0 0.0 0.0 0.0")),
            "");
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  const double tiny_scales[] = {0x1p-60, 0x1p-20, 0x1p-3, 1.0, 0x1p+3, 0x1p+20, 0x1p+60, 0x1p+300};
  const double huge_values[] = {-5.486124068813628e+303, 5.486124068813628e+303, -1e300, -1.7e308, -0x1p+200, -1.0};
  Tally tally;
  for (const auto& pm : perms)
    for (const double ts : tiny_scales)
      for (const double hv : huge_values)
        for (int flip = 0; flip < 2; ++flip) {  // flip: the origin's y on the other side (a hit or edge)
          io::Case c = parse("triangle 0 0 0 0 0 1 1 0 0 0 -1 0 0 0 0");
          for (int p = 0; p < 5; ++p)
            for (int k = 0; k < 3; ++k) {
              double v = base[3 * p + k];
              if (v != 0 && std::fabs(v) < 1e-300) v *= ts;
              if (p == 3 && k == 1) v = hv;
              if (flip && p == 0 && k == 1) v = -v;
              c.v[static_cast<std::size_t>(3 * p + pm[k])] = v;
            }
          tally.run(c);
        }
  EXPECT_EQ(tally.bad, 0u);
  std::printf("subnormal/huge mixes: %zu cases\n", tally.cases);
}

/// Every case fuzz_kernels has found against certified (data/regressions/certified.txt) agrees with exact.
TEST(Certified, AgreesWithExactOnEveryFuzzRegression) {
  std::ifstream in(std::string(RAYPROOF_DATA_DIR) + "/regressions/certified.txt");
  ASSERT_TRUE(in);
  std::size_t n = 0;
  for (const auto& e : io::read_cases(in)) {
    const auto* c = std::get_if<io::Case>(&e);
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(disagreement(*c), "");
    ++n;
  }
  EXPECT_GE(n, 3u);
}

/// Regression (fuzz_kernels, second case of data/regressions/certified.txt): a direction whose
/// |d|_1 is below 2^-1025 made stage 1's k = 2^-49 |d|_1 underflow to 0, so its error bounds kept
/// only their 2^-1000 underflow term while the products d x (p - o) were of order 1e-9 x 5e303:
/// a miss came out interior. That direction scaled by powers of two, beside coordinates up to
/// 1.7e308, with the origin outside or inside the triangle's range, along each axis.
TEST(Certified, AgreesWithExactOnShortDirectionsBesideHugeCoordinates) {
  // Powers of two times the fuzz case's direction: |d|_1 from about 2^-1056 to 2^-956.
  const double dir_scales[] = {0x1p-20, 0x1p-8, 0x1p-2, 1.0, 0x1p+2, 0x1p+8, 0x1p+40, 0x1p+77, 0x1p+80};
  const double huge_values[] = {-5.48878615954232e+303, -1.7e308, -1e250, -0x1p+200, 5.48878615954232e+303};
  Tally tally;
  for (const double ds : dir_scales)
    for (const double hv : huge_values)
      for (int axis = 0; axis < 3; ++axis)
        for (int flip = 0; flip < 2; ++flip) {  // flip: the origin inside the triangle's y range (a hit)
          // The fuzz case, its direction rescaled, the huge origin coordinate replaced, rotated.
          const double o[3] = {-2.8777739825090034e+76, flip ? -1e200 : hv, 2.566584306689592e-306};
          const double d[3] = {1.35807730622e-312 * ds, 0.0, 2.074791e-317 * ds};
          const double p[3][3] = {{2.0, 0.0, 5.311465295e-315},
                                  {0.0, -3.105036184601462e+231, 7.264113603438767e-308},
                                  {1.2160346153844507e+58, 0.0, 0.0}};
          io::Case c = parse("triangle 0 0 0 1 0 0 0 0 0 1 0 0 0 1 0");
          auto put = [&](int slot, const double (&v)[3]) {
            for (int k = 0; k < 3; ++k) c.v[static_cast<std::size_t>(3 * slot + (k + axis) % 3)] = v[k];
          };
          put(0, o), put(1, d), put(2, p[0]), put(3, p[1]), put(4, p[2]);
          tally.run(c);
        }
  EXPECT_EQ(tally.bad, 0u);
  std::printf("short directions beside huge coordinates: %zu cases\n", tally.cases);
}

/// Regression (fuzz_kernels, third case of data/regressions/certified.txt): the double-double t
/// compared its error bound against dmin |D.hi|, which overflowed for |d . n| above ~1e154, so any
/// t passed. That case with its huge coordinate and the whole case scaled by powers of two (t is
/// unchanged by a common scale, |d . n| moves by 2^(3s)): t must be within one ulp of exact.
TEST(Certified, AgreesWithExactWhenTheDenominatorSquaredOverflows) {
  const io::Case base = parse(
      "triangle -131072.0000000027 -595821443.5137254 -595821443.5137254 -595821443.5137254 -595821443.5136949 "
      "-595821443.5137254 -595852797.5115587 -595821443.5137254 -595821443.5137254 2.0628714955843752e+283 "
      "-595821443.9921495 -595821443.5137254 0.0 0.0 0.0");
  Tally tally;
  for (const int huge_shift : {-800, -500, -300, -150, -60, 0, 20, 60})
    for (const int s : {-200, -100, -20, 0, 10, 30}) {
      io::Case c = base;
      c.v[9] = std::ldexp(c.v[9], huge_shift);
      for (int i = 0; i < 15; ++i) c.v[static_cast<std::size_t>(i)] = std::ldexp(c.v[static_cast<std::size_t>(i)], s);
      if (!std::isfinite(c.v[9]) || c.v[9] == 0) continue;
      tally.run(c);
    }
  EXPECT_EQ(tally.bad, 0u);
  EXPECT_GE(tally.cases, 40u);
  std::printf("huge denominators: %zu cases\n", tally.cases);
}

/// Spheres seen from far away (the origin 2^0 .. 2^40 radii from the centre), rays through random
/// points of the sphere and just past its rim: the double-double stage's b^2 - a c loses (|e| / r)^2 of
/// precision there and hands over to the cancellation-free a r^2 - |d x e|^2 (without that hand-over
/// the near-tangent test below leaves 5% to GMP instead of 0.4%). Every answer is checked against exact.
TEST(Certified, AgreesWithExactFromFarAway) {
  std::mt19937_64 g(29);
  std::uniform_real_distribution<double> U(-1, 1);
  Tally t;
  for (int i = 0; i < 6000; ++i) {
    const Vec3<double> c{U(g), U(g), U(g)};
    const double r = 0.25 + 0.5 * std::fabs(U(g));
    const Vec3<double> dir = normalize(Vec3<double>{U(g), U(g), U(g) + 0.01});
    const Vec3<double> o = c + (r * std::ldexp(1.0 + std::fabs(U(g)), static_cast<int>(g() % 41))) * dir;
    // A point on the sphere (or 1% outside its rim) in the hemisphere facing o.
    Vec3<double> q = normalize(Vec3<double>{U(g), U(g), U(g)});
    if (dot(q, dir) < 0) q = -1.0 * q;
    const Vec3<double> target = c + (i % 3 == 0 ? 1.01 * r : r) * q;
    t.run(sphere_case(o, target - o, c, r));
  }
  EXPECT_EQ(t.bad, 0u);
  if (certified::dd::available()) {
    EXPECT_LT(t.fallbacks, t.cases / 50);
  }
  std::printf("far away: %zu cases, %zu fallbacks\n", t.cases, t.fallbacks);
}

/// Rays within a few thousand ulps of tangency to spheres at scales 2^-20 .. 2^40: the discriminant
/// cancels to a tiny fraction of a r^2 (the double-double path then holds a low part that is a large
/// fraction of its high part, which its square root must not mistake for a rounding error; this
/// caught exactly that). Every case against exact, and with FMA most decided without GMP.
TEST(Certified, AgreesWithExactNearTangentAtEveryScale) {
  std::mt19937_64 g(23);
  std::uniform_real_distribution<double> U(-1, 1);
  Tally t;
  for (int i = 0; i < 6000; ++i) {
    const double scale = std::ldexp(1.0, static_cast<int>(g() % 61) - 20);
    const Vec3<double> c{U(g) * scale, U(g) * scale, U(g) * scale};
    const double r = (0.1 + std::fabs(U(g))) * scale;
    const Vec3<double> o{c.x + 5 * r * U(g), c.y + 5 * r * U(g), c.z + 7 * r};
    // Aim past the centre by lambda along a unit side vector perpendicular to w = c - o: the line then
    // passes the centre at distance lambda |w| / sqrt(|w|^2 + lambda^2), which is r for this lambda.
    const Vec3<double> w = c - o, side = normalize(cross(w, Vec3<double>{U(g), U(g), U(g)}));
    const double ww = dot(w, w), lambda = r * std::sqrt(ww / (ww - r * r));
    Vec3<double> target = c + lambda * side;
    const int k = static_cast<int>(g() % 4096);
    for (int j = 0; j < k; ++j) target.x = (i & 1) ? certified::next_above(target.x) : certified::next_below(target.x);
    t.run(sphere_case(o, target - o, c, r));
  }
  EXPECT_EQ(t.bad, 0u);
  // Double-double pins nearly all of these; the x87 path's 11 extra bits leave about half to GMP.
  if (certified::dd::available()) {
    EXPECT_LT(t.fallbacks, t.cases / 20);
  }
  std::printf("near-tangent: %zu cases, %zu fallbacks\n", t.cases, t.fallbacks);
}

/// The double-double stage for triangles the double stage leaves (rays near the plane, an edge or a
/// vertex) decides a good share of near-parallel rays on its own, and each of its answers equals the
/// exact one (class and t within one ulp).
TEST(Certified, DoubleDoubleTriangleStageAgreesWithExact) {
#if RAYPROOF_FMA_PATH != 0
  if (!certified::dd::available()) GTEST_SKIP() << "no FMA here (or RAYPROOF_CERTIFIED_NO_FMA set)";
  const gen::Family* f = gen::find_family("tri_near_parallel");
  ASSERT_NE(f, nullptr);
  std::size_t left = 0, decided = 0;
  for (const io::Case& c : gen::generate(*f, 4000, 5, gen::Precision::float64)) {
    const Ray<double> ray{{c.v[0], c.v[1], c.v[2]}, {c.v[3], c.v[4], c.v[5]}};
    const Triangle<double> tri{{c.v[6], c.v[7], c.v[8]}, {c.v[9], c.v[10], c.v[11]}, {c.v[12], c.v[13], c.v[14]}};
    if (!ray.valid() || certified::detail::triangle_fast(ray, tri, [] { return std::optional<Hit<double>>(); })) continue;
    ++left;
    const auto h = certified::dd::triangle_near(ray, tri);
    if (!h) continue;
    ++decided;
    const io::CaseResult want = verify::exact_classify(c);
    const io::CaseResult got = make_result(io::Kind::triangle, h->contact, h->t, h->t2);
    ASSERT_EQ(got.contact, want.contact) << io::format_case(c);
    ASSERT_LE(verify::t_error_ulps(got, want, Precision::float64), 1u) << io::format_case(c);
  }
  EXPECT_GT(left, 100u);
  EXPECT_GT(decided, left / 10) << decided << " of " << left;
  std::printf("double-double triangle stage: decided %zu of %zu left by the double stage\n", decided, left);
#else
  GTEST_SKIP() << "no FMA path on this target";
#endif
}
