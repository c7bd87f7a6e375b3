/// Triangle/triangle classes (docs/tritri.md): the certified classifier (rayproof/certified/tritri.h)
/// equals CGAL's exact class (rayproof::exact::tritri) on every pair family, under the 36 vertex
/// permutations and the swap of the two triangles, and under exact transformations (power-of-two
/// scales, axis permutations with sign flips); hand-written cases of every class; the header-only
/// try_tritri is undecided or exact; the classic float/double kernels (Möller, Guigue–Devillers)
/// are right on easy pairs, and their wrong answers on the hard families are counted and printed.
#include "rayproof/certified/tritri.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gen/families.h"
#include "gen/rng.h"
#include "gen/tritri_families.h"
#include "methods/method.h"
#include "verify/certified_method.h"
#include "verify/differential.h"
#include "verify/exact_method.h"
#include "rayproof/tritri.h"
#include "rayproof/verify/exact.h"

namespace rayproof {
namespace {

using V = Vec3<double>;
using T = Triangle<double>;

std::string show(const T& a, const T& b) {
  std::string s;
  char buf[64];
  for (const V* v : {&a.p0, &a.p1, &a.p2, &b.p0, &b.p1, &b.p2}) {
    std::snprintf(buf, sizeof buf, "(%a %a %a) ", v->x, v->y, v->z);
    s += buf;
  }
  return s;
}

/// The six vertex orders of a triangle.
std::array<T, 6> orders(const T& t) {
  return {T{t.p0, t.p1, t.p2}, T{t.p1, t.p2, t.p0}, T{t.p2, t.p0, t.p1},
          T{t.p0, t.p2, t.p1}, T{t.p2, t.p1, t.p0}, T{t.p1, t.p0, t.p2}};
}

T map(const T& t, auto f) { return {f(t.p0), f(t.p1), f(t.p2)}; }

struct Hand {
  const char* what;
  T a, b;
  TriTri want;
};

const T kBase{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}};  // in z = 0

const std::vector<Hand>& hand_cases() {
  static const std::vector<Hand> h = {
      {"apart along z", kBase, {{0, 0, 1}, {4, 0, 1}, {0, 4, 1}}, TriTri::disjoint},
      {"planes cross, segments apart", kBase, {{5, 5, -1}, {5, 5, 1}, {6, 5, 0}}, TriTri::disjoint},
      {"pierces the middle", kBase, {{1, 1, -1}, {1, 1, 1}, {2, 1, 0}}, TriTri::crossing},
      {"edge through an edge, then inside", kBase, {{1, -1, -1}, {1, 1, 1}, {1, 2, 0}}, TriTri::crossing},
      {"vertex on the face", kBase, {{1, 1, 0}, {1, 1, 1}, {2, 1, 1}}, TriTri::touching},
      {"vertex on an edge", kBase, {{2, 0, 0}, {2, 1, 1}, {3, -1, 1}}, TriTri::touching},
      {"shared vertex", kBase, {{0, 0, 0}, {-1, 0, 1}, {0, -1, 1}}, TriTri::touching},
      {"shared edge, folded", kBase, {{0, 0, 0}, {4, 0, 0}, {0, 0, 4}}, TriTri::touching},
      {"edge crosses an edge, only that point", kBase, {{1, -1, -1}, {1, 1, 1}, {1, -2, 0}}, TriTri::touching},
      {"edge lies on the face", kBase, {{1, 1, 0}, {2, 1, 0}, {1, 1, 3}}, TriTri::touching},
      {"edge on the face, beyond it", kBase, {{1, 1, 0}, {9, 1, 0}, {1, 1, 3}}, TriTri::touching},
      {"segment ends meet exactly", kBase, {{4, 0, -1}, {4, 0, 1}, {8, 0, 0}}, TriTri::touching},
      {"coplanar, same", kBase, kBase, TriTri::coplanar_overlap},
      {"coplanar, inside", kBase, {{1, 1, 0}, {2, 1, 0}, {1, 2, 0}}, TriTri::coplanar_overlap},
      {"coplanar, crossing edges", kBase, {{-1, 1, 0}, {5, 1, 0}, {2, -3, 0}}, TriTri::coplanar_overlap},
      {"coplanar, shared edge, other side", kBase, {{0, 0, 0}, {4, 0, 0}, {2, -3, 0}}, TriTri::coplanar_touching},
      {"coplanar, vertex to vertex", kBase, {{4, 0, 0}, {8, 0, 0}, {8, -4, 0}}, TriTri::coplanar_touching},
      {"coplanar, vertex on an edge", kBase, {{2, 2, 0}, {4, 4, 0}, {3, 5, 0}}, TriTri::coplanar_touching},
      {"coplanar, apart", kBase, {{5, 5, 0}, {6, 5, 0}, {5, 6, 0}}, TriTri::disjoint},
      {"coplanar, apart across the hypotenuse", kBase, {{3, 2, 0}, {2, 3, 0}, {4, 4, 0}}, TriTri::disjoint},
      {"collinear", kBase, {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, TriTri::degenerate},
      {"one point", {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}, kBase, TriTri::degenerate},
      {"NaN", kBase, {{0, 0, std::nan("")}, {1, 0, 0}, {0, 1, 0}}, TriTri::invalid},
      {"infinite", kBase, {{0, 0, INFINITY}, {1, 0, 0}, {0, 1, 0}}, TriTri::invalid},
  };
  return h;
}

TEST(TriTri, HandWrittenCasesEveryClass) {
  for (const Hand& h : hand_cases()) {
    SCOPED_TRACE(h.what);
    EXPECT_EQ(certified::tritri(h.a, h.b), h.want) << to_string(certified::tritri(h.a, h.b));
    EXPECT_EQ(exact::tritri(h.a, h.b), h.want) << to_string(exact::tritri(h.a, h.b));
    const std::optional<TriTri> f = certified::try_tritri(h.a, h.b);
    ASSERT_TRUE(f.has_value());  // small integers: the filter decides
    EXPECT_EQ(*f, h.want);
    // Extreme magnitudes, subnormal coordinates too: the same classes (GMP decides what the
    // expansions cannot).
    for (int e : {600, -600, 1000, -1065}) {
      auto s = [e](V v) { return V{std::ldexp(v.x, e), std::ldexp(v.y, e), std::ldexp(v.z, e)}; };
      EXPECT_EQ(certified::tritri(map(h.a, s), map(h.b, s)), h.want) << e;
    }
  }
  // The six-vertex overload.
  EXPECT_EQ(certified::tritri(V{0, 0, 0}, V{4, 0, 0}, V{0, 4, 0}, V{1, 1, -1}, V{1, 1, 1}, V{2, 1, 0}),
            TriTri::crossing);
}

TEST(TriTri, ClassNamesRoundTrip) {
  for (std::size_t i = 0; i < kTriTriNames.size(); ++i) {
    const auto c = static_cast<TriTri>(i);
    EXPECT_EQ(tritri_from_string(to_string(c)), c);
  }
  EXPECT_FALSE(tritri_from_string("nope"));
}

constexpr std::uint64_t kSeed = 20260538;

/// The pair under vertex orders and the swap of the two triangles: all 72 for the first 20 pairs of a
/// family, four drawn at random for the others (the suite also runs under ASan).
template <class F>
void for_variants(gen::Rng& rng, std::size_t index, const gen::TriPair& p, F&& check) {
  const std::array<T, 6> oa = orders(p.a), ob = orders(p.b);
  if (index <= 20) {
    for (const T& a : oa)
      for (const T& b : ob) {
        check(a, b);
        check(b, a);
      }
    return;
  }
  for (int k = 0; k < 4; ++k) {
    const T& a = oa[rng.below(6)];
    const T& b = ob[rng.below(6)];
    if (rng.coin()) check(a, b);
    else check(b, a);
  }
}

std::size_t count_for(const std::string& family) { return family == "extreme" ? 120 : 200; }

/// certified == CGAL on every family; the expected class of the construction where it has one;
/// every vertex order and the swap; a random exact transformation; try_tritri undecided or equal.
TEST(TriTri, CertifiedEqualsExactOnEveryFamily) {
  gen::Rng rng(kSeed);
  std::size_t pairs = 0, undecided = 0;
  for (const gen::TriTriFamily& f : gen::tritri_families()) {
    SCOPED_TRACE(f.name);
    std::size_t fam_undecided = 0, index = 0;
    for (const gen::TriPair& p : gen::generate_tritri(f, count_for(f.name), kSeed)) {
      ++pairs;
      const TriTri ex = exact::tritri(p.a, p.b);
      if (p.expected) {
        ASSERT_EQ(ex, *p.expected) << show(p.a, p.b) << " exact " << to_string(ex);
      }
      ASSERT_EQ(certified::tritri(p.a, p.b), ex) << show(p.a, p.b);
      const std::optional<TriTri> fast = certified::try_tritri(p.a, p.b);
      if (fast) ASSERT_EQ(*fast, ex) << show(p.a, p.b);
      else ++fam_undecided;
      for_variants(rng, ++index, p, [&](const T& a, const T& b) { ASSERT_EQ(certified::tritri(a, b), ex) << show(a, b); });
      // An exact transformation: axes permuted with sign flips, a power-of-two scale that keeps
      // every coordinate normal and finite; CGAL on it too.
      const int perm = static_cast<int>(rng.below(3));
      const bool swap_yz = rng.coin();
      const double sx = rng.sign(), sy = rng.sign();
      const int e = f.name == "extreme" || f.name == "near_coplanar" ? 0 : rng.irange(-200, 200);
      auto tr = [&](V v) {
        V w{v[perm], v[(perm + 1) % 3], v[(perm + 2) % 3]};
        if (swap_yz) std::swap(w.y, w.z);
        return V{std::ldexp(sx * w.x, e), std::ldexp(sy * w.y, e), std::ldexp(w.z, e)};
      };
      const T ta = map(p.a, tr), tb = map(p.b, tr);
      ASSERT_EQ(certified::tritri(ta, tb), ex) << show(ta, tb);
      if (index % 4 == 1) {  // CGAL on some transformed pairs too (its cost dominates under ASan)
        ASSERT_EQ(exact::tritri(tb, ta), ex) << show(tb, ta);
      }
    }
    // Inside the expansions' window every sign is decided without GMP.
    if (f.name != "extreme") {
      EXPECT_EQ(fam_undecided, 0u);
    }
    undecided += fam_undecided;
  }
  EXPECT_GE(pairs, 3000u);  // 15 families of 200 pairs and the extreme one of 120
  EXPECT_GT(undecided, 0u);  // the extreme family needs the fallback
}

/// Whether they share a point, zero-area triangles included: certified == CGAL on every family,
/// the construction's answer where it has one, meets(class) for two triangles of positive area,
/// every vertex order and the swap; try_tritri_meets undecided or equal.
TEST(TriTri, MeetsEqualsExactOnEveryFamily) {
  gen::Rng rng(kSeed + 1);
  int degenerate_meeting = 0, degenerate_apart = 0;
  for (const gen::TriTriFamily& f : gen::tritri_families()) {
    SCOPED_TRACE(f.name);
    std::size_t index = 0;
    for (const gen::TriPair& p : gen::generate_tritri(f, count_for(f.name) / 2, kSeed)) {
      const bool ex = exact::tritri_meets(p.a, p.b);
      if (p.expected_meets) {
        ASSERT_EQ(ex, *p.expected_meets) << show(p.a, p.b);
      }
      const TriTri c = certified::tritri(p.a, p.b);
      if (c == TriTri::degenerate) (ex ? degenerate_meeting : degenerate_apart) += 1;
      else ASSERT_EQ(ex, meets(c)) << show(p.a, p.b);
      const std::optional<bool> fast = certified::try_tritri_meets(p.a, p.b);
      if (fast) {
        ASSERT_EQ(*fast, ex) << show(p.a, p.b);
      }
      for_variants(rng, ++index, p, [&](const T& a, const T& b) { ASSERT_EQ(certified::tritri_meets(a, b), ex) << show(a, b); });
    }
  }
  EXPECT_GT(degenerate_meeting, 50);
  EXPECT_GT(degenerate_apart, 50);
}

TEST(TriTri, MeetsZeroAreaHandCases) {
  const T point_in{{1, 1, 0}, {1, 1, 0}, {1, 1, 0}}, point_out{{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  const T through{{1, 1, -1}, {1, 1, 1}, {1, 1, 0}}, beside{{5, 5, -1}, {5, 5, 1}, {5, 5, 0}};
  const T on_edge_line{{-2, 0, 0}, {-1, 0, 0}, {0, 0, 0}}, before_edge{{-3, 0, 0}, {-2, 0, 0}, {-1, 0, 0}};
  const T in_plane_across{{-1, 1, 0}, {1, 1, 0}, {3, 1, 0}}, in_plane_apart{{-3, 1, 0}, {-2, 1, 0}, {-1, 1, 0}};
  const T crossing_segment{{1, 0, -1}, {1, 0, 1}, {1, 0, 0}}, skew_segment{{0, 0, 1}, {2, 0, 1}, {4, 0, 1}};
  const struct {
    const char* what;
    T a, b;
    bool want;
  } cases[] = {
      {"point in the face", point_in, kBase, true},     {"point above", point_out, kBase, false},
      {"segment through", through, kBase, true},        {"segment beside", beside, kBase, false},
      {"segment to the vertex", on_edge_line, kBase, true}, {"segment short of the vertex", before_edge, kBase, false},
      {"segment across, in plane", in_plane_across, kBase, true}, {"segment apart, in plane", in_plane_apart, kBase, false},
      {"point on a segment", T{{1, 0, 0}, {1, 0, 0}, {1, 0, 0}}, crossing_segment, true},
      {"segments crossing", crossing_segment, T{{0, 0, 0}, {2, 0, 0}, {1, 0, 0}}, true},
      {"segments skew", crossing_segment, T{{0, 1, 0}, {2, 1, 0}, {1, 1, 0}}, false},
      {"segments in one plane, lines cross beyond one", T{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}},
       T{{3, -1, 0}, {3, 1, 0}, {3, 0, 0}}, false},
      {"segments on one line, apart", before_edge, T{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, false},
      {"segments on one line, touching", on_edge_line, T{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, true},
      {"parallel segments", skew_segment, T{{0, 0, 0}, {2, 0, 0}, {4, 0, 0}}, false},
      {"points equal", point_in, point_in, true},       {"points apart", point_in, point_out, false},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.what);
    EXPECT_EQ(certified::tritri(c.a, c.b), TriTri::degenerate);
    EXPECT_EQ(certified::tritri_meets(c.a, c.b), c.want);
    EXPECT_EQ(exact::tritri_meets(c.a, c.b), c.want);
    EXPECT_EQ(certified::try_tritri_meets(c.a, c.b), std::optional<bool>(c.want));
  }
}

/// Pairs on a 7^3 integer grid, biased to share vertices and planes: every sign pattern of the
/// classifier (zeros everywhere, collinear and coincident vertices) against CGAL, class and contact.
TEST(TriTri, CertifiedEqualsExactOnSmallIntegerGrid) {
  gen::Rng rng(kSeed + 3);
  auto point = [&] {
    const double x = static_cast<double>(rng.range(-3, 3)), y = static_cast<double>(rng.range(-3, 3)),
                 z = static_cast<double>(rng.range(-3, 3));
    return V{x, y, z};
  };
  std::array<int, kTriTriNames.size()> seen{};
  for (int i = 0; i < 1500; ++i) {
    T a{point(), point(), point()}, b{point(), point(), point()};
    if (rng.coin()) b.p0 = a.p1;
    if (rng.chance(1, 4)) b.p1 = a.p2;
    if (rng.chance(1, 3)) {
      a.p1.z = a.p2.z = b.p0.z = b.p1.z = b.p2.z = a.p0.z;
    }
    const TriTri ex = exact::tritri(a, b);
    ++seen[static_cast<std::size_t>(ex)];
    ASSERT_EQ(certified::tritri(a, b), ex) << show(a, b);
    ASSERT_EQ(certified::tritri_meets(a, b), exact::tritri_meets(a, b)) << show(a, b);
  }
  for (std::size_t c = 0; c + 1 < seen.size(); ++c) EXPECT_GT(seen[c], 10) << kTriTriNames[c];
}

/// Every class occurs among the families (so the comparison above exercises each).
TEST(TriTri, FamiliesCoverEveryClass) {
  std::array<int, kTriTriNames.size()> seen{};
  for (const gen::TriTriFamily& f : gen::tritri_families())
    for (const gen::TriPair& p : gen::generate_tritri(f, 40, kSeed)) ++seen[static_cast<std::size_t>(certified::tritri(p.a, p.b))];
  for (std::size_t i = 0; i + 1 < seen.size(); ++i) EXPECT_GT(seen[i], 0) << kTriTriNames[i];
}

TEST(TriTri, FamiliesAreDeterministic) {
  for (const gen::TriTriFamily& f : gen::tritri_families()) {
    const auto x = gen::generate_tritri(f, 30, 7), y = gen::generate_tritri(f, 50, 7);
    for (std::size_t i = 0; i < x.size(); ++i) EXPECT_EQ(show(x[i].a, x[i].b), show(y[i].a, y[i].b)) << f.name;
  }
}

/// The near-coplanar knob: k = 0 is the coplanar pair; a lift of k ulps is never coplanar.
TEST(TriTri, NearCoplanarKnob) {
  for (std::size_t i = 0; i < 40; ++i) {
    const gen::TriPair flat = gen::near_coplanar_pair(kSeed, i, 0);
    const TriTri c0 = certified::tritri(flat.a, flat.b);
    EXPECT_TRUE(c0 == TriTri::coplanar_overlap || c0 == TriTri::coplanar_touching || c0 == TriTri::disjoint);
    for (int k : {1, 16, 1 << 20}) {
      const gen::TriPair lifted = gen::near_coplanar_pair(kSeed, i, k);
      const TriTri c = certified::tritri(lifted.a, lifted.b);
      EXPECT_NE(c, TriTri::coplanar_overlap);
      EXPECT_NE(c, TriTri::coplanar_touching);
      EXPECT_EQ(c, exact::tritri(lifted.a, lifted.b));
    }
  }
}

// ---- the classic kernels ----

Triangle<float> to_float(const T& t) {
  auto f = [](V v) { return Vec3<float>{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)}; };
  return {f(t.p0), f(t.p1), f(t.p2)};
}
T to_double(const Triangle<float>& t) {
  auto d = [](Vec3<float> v) { return V{v.x, v.y, v.z}; };
  return {d(t.p0), d(t.p1), d(t.p2)};
}

struct Tally {
  int pairs[2] = {}, meet[2] = {};  // float, double
  int wrong[4] = {};                // Möller float, Möller double, GD float, GD double
  int false_neg[4] = {};
};

/// The kernels against the exact answer: double on the pair, float on the pair rounded to float
/// (judged against the exact class of the rounded pair). Pairs with a zero-area or non-finite
/// triangle in that precision are left out: the kernels do not define them.
Tally tally(const std::vector<gen::TriPair>& pairs) {
  Tally t;
  auto judged = [](TriTri c) { return c != TriTri::degenerate && c != TriTri::invalid; };
  for (const gen::TriPair& p : pairs) {
    const Triangle<float> fa = to_float(p.a), fb = to_float(p.b);
    const TriTri ex[2] = {certified::tritri(to_double(fa), to_double(fb)), certified::tritri(p.a, p.b)};
    for (int prec = 0; prec < 2; ++prec) {
      if (!judged(ex[prec])) continue;
      ++t.pairs[prec];
      t.meet[prec] += meets(ex[prec]);
      const bool got[2] = {prec == 0 ? tritri_moller(fa, fb) : tritri_moller(p.a, p.b),
                           prec == 0 ? tritri_guigue_devillers(fa, fb) : tritri_guigue_devillers(p.a, p.b)};
      for (int m = 0; m < 2; ++m) {
        const int k = 2 * m + prec;
        t.wrong[k] += got[m] != meets(ex[prec]);
        t.false_neg[k] += meets(ex[prec]) && !got[m];
      }
    }
  }
  return t;
}

TEST(TriTriKernels, EasyPairsRight) {
  for (const char* name : {"far_apart", "crossing"}) {
    const Tally t = tally(gen::generate_tritri(*gen::find_tritri_family(name), 300, kSeed));
    EXPECT_EQ(t.pairs[0], 300) << name;
    EXPECT_EQ(t.pairs[1], 300) << name;
    for (int k = 0; k < 4; ++k) EXPECT_EQ(t.wrong[k], 0) << name << " kernel " << k;
  }
  // The front door dispatches to the two kernels.
  const T b{{1, 1, -1}, {1, 1, 1}, {2, 1, 0}};
  EXPECT_TRUE(tritri_intersect(kBase, b, TriTriMethod::moller));
  EXPECT_TRUE(tritri_intersect(kBase, b, TriTriMethod::guigue_devillers));
  EXPECT_FALSE(tritri_intersect(kBase, T{{0, 0, 1}, {4, 0, 1}, {0, 4, 1}}));
}

/// Guigue–Devillers decides by signs alone: where its arithmetic is exact (small integer coordinates:
/// every orient3d and orient2d is exact in double) it must be exactly right, on every sign pattern
/// (shared vertices and edges, vertices on faces, coplanar pairs are common on a 9^3 grid). This
/// checks its permutations and its coplanar branch. Möller divides, so it is not held to this.
TEST(TriTriKernels, GuigueDevillersExactOnSmallIntegers) {
  gen::Rng rng(kSeed + 2);
  auto point = [&] {
    const double x = static_cast<double>(rng.range(-4, 4)), y = static_cast<double>(rng.range(-4, 4)),
                 z = static_cast<double>(rng.range(-4, 4));
    return V{x, y, z};
  };
  std::array<int, kTriTriNames.size()> seen{};
  int checked = 0;
  for (int i = 0; i < 20000 && checked < 6000; ++i) {
    T a{point(), point(), point()}, b{point(), point(), point()};
    if (rng.coin()) b.p0 = a.p1;  // shared vertices and edges more often
    if (rng.chance(1, 4)) b.p1 = a.p2;
    if (rng.chance(1, 3)) {  // coplanar more often: b in a's plane z = a.z when a is flat in z
      a.p1.z = a.p0.z;
      a.p2.z = a.p0.z;
      b.p0.z = b.p1.z = b.p2.z = a.p0.z;
    }
    const TriTri ex = certified::tritri(a, b);
    if (ex == TriTri::degenerate) continue;
    ++checked;
    ++seen[static_cast<std::size_t>(ex)];
    ASSERT_EQ(tritri_guigue_devillers(a, b), meets(ex)) << show(a, b) << to_string(ex);
    const Triangle<float> fa = to_float(a), fb = to_float(b);
    ASSERT_EQ(tritri_guigue_devillers(fa, fb), meets(ex)) << show(a, b) << to_string(ex);
  }
  EXPECT_EQ(checked, 6000);
  for (std::size_t c = 0; c + 2 < seen.size(); ++c) EXPECT_GT(seen[c], 20) << kTriTriNames[c];
}

/// Wrong answers per family (printed; docs/tritri.md's table is this output). Asserted only where
/// it must hold and what was observed: both kernels fail in float on the shared-edge and
/// vertex-on-face families, never on far-apart or clearly crossing pairs.
TEST(TriTriKernels, FailuresOnHardFamiliesCounted) {
  std::printf("%-18s %6s %6s %5s %5s | %11s %11s %11s %11s\n", "family", "pairs_f", "pairs_d", "meetf", "meetd", "moller_f",
              "moller_d", "gd_f", "gd_d");
  for (const gen::TriTriFamily& f : gen::tritri_families()) {
    const Tally t = tally(gen::generate_tritri(f, 400, kSeed));
    std::printf("%-18s %6d %6d %5d %5d |", f.name.c_str(), t.pairs[0], t.pairs[1], t.meet[0], t.meet[1]);
    for (int k : {0, 1, 2, 3}) std::printf(" %4d (%4d)", t.wrong[k], t.false_neg[k]);
    std::printf("\n");
    if (f.name == "shared_edge" || f.name == "vertex_on_face") {
      EXPECT_GT(t.wrong[0], 0) << f.name;  // Möller, float
      EXPECT_GT(t.wrong[2], 0) << f.name;  // Guigue–Devillers, float
    }
    if (f.name == "far_apart" || f.name == "crossing") {
      for (int k : {0, 1, 2, 3}) EXPECT_EQ(t.wrong[k], 0) << f.name;
    }
  }
  std::printf("(wrong answers, false negatives in brackets; float columns on the pair rounded to float)\n");
}

// ---- pairs as cases: the methods of the registry on the generated tritri families ----

/// The tritri methods: exact, certified and the four classic ones, as the tool registers them.
const MethodRegistry& pair_registry() {
  static const MethodRegistry reg = [] {
    MethodRegistry r;
    verify::register_exact_method(r);
    verify::register_certified_method(r);
    register_tritri_methods(r);
    return r;
  }();
  return reg;
}

std::vector<const gen::Family*> pair_case_families() {
  std::vector<const gen::Family*> out;
  for (const gen::Family& f : gen::families())
    if (f.kind == io::Kind::tritri) out.push_back(&f);
  return out;
}

/// Every pair family is a case family, and its double cases are the pairs of generate_tritri.
TEST(TriTriCases, FamiliesAreThePairFamiliesAsCases) {
  const auto fams = pair_case_families();
  ASSERT_EQ(fams.size(), gen::tritri_families().size());
  for (const gen::Family* f : fams) {
    const gen::TriTriFamily* pf = gen::find_tritri_family(f->name.substr(7));
    ASSERT_NE(pf, nullptr) << f->name;
    const auto cases = gen::generate(*f, 30, kSeed, gen::Precision::float64);
    const auto pairs = gen::generate_tritri(*pf, 30, kSeed);
    ASSERT_EQ(cases.size(), pairs.size());
    for (std::size_t i = 0; i < cases.size(); ++i) {
      EXPECT_EQ(cases[i].kind, io::Kind::tritri);
      EXPECT_EQ(cases[i].family, f->name);
      const io::Case want = gen::tritri_case(pairs[i]);
      for (std::size_t k = 0; k < 18; ++k)
        ASSERT_EQ(std::bit_cast<std::uint64_t>(cases[i].v[k]), std::bit_cast<std::uint64_t>(want.v[k])) << f->name << " " << i;
    }
  }
}

/// The certified method promises the exact class: no wrong class on any family, in double or on the
/// float-built cases, and it counts the pairs that needed GMP.
TEST(TriTriCases, CertifiedNeverWrongOnAnyFamily) {
  const Method* cert = pair_registry().find("certified");
  ASSERT_NE(cert, nullptr);
  ASSERT_TRUE(cert->supports(io::Kind::tritri));
  std::vector<io::Case> cases;
  for (const gen::Family* f : pair_case_families())
    for (auto p : {gen::Precision::float64, gen::Precision::float32}) {
      const auto part = gen::generate(*f, 60, kSeed + 1, p);
      cases.insert(cases.end(), part.begin(), part.end());
    }
  const verify::ExactAnswers exact = verify::exact_answers(cases);
  const verify::Comparison cmp = verify::compare(cases, exact, {cert}, 10);
  const verify::Stats total = cmp.total("certified");
  EXPECT_EQ(total.cases, cases.size());
  EXPECT_EQ(total.class_errors(), 0u);
  EXPECT_EQ(total.promised, cases.size());
  EXPECT_EQ(total.promise_broken, 0u);
  EXPECT_TRUE(cmp.mismatches.empty());
  EXPECT_GT(cmp.stats.at({"certified", "tritri_extreme"}).fallbacks, 0u);  // 2^+-600 needs GMP
  EXPECT_EQ(cmp.stats.at({"certified", "tritri_crossing"}).fallbacks, 0u);
}

/// The classic kernels judged through the registry (coarse answers, float methods on the rounded
/// pair) count exactly the wrong answers that calling the kernels directly counts (tally above),
/// family by family: the same pairs judged, the same false "meets" and false "disjoint".
TEST(TriTriCases, ClassicFailuresEqualTheDirectCount) {
  const char* names[4] = {"moller-float", "moller-double", "gd-float", "gd-double"};  // tally's order
  std::vector<const Method*> methods;
  for (const char* n : names) {
    methods.push_back(pair_registry().find(n));
    ASSERT_NE(methods.back(), nullptr) << n;
  }
  constexpr std::size_t kCount = 150;
  std::size_t wrong_seen = 0;
  for (const gen::Family* f : pair_case_families()) {
    const auto cases = gen::generate(*f, kCount, kSeed, gen::Precision::float64);
    const verify::Comparison cmp = verify::compare(cases, verify::exact_answers(cases), methods, 0);
    const Tally direct = tally(gen::generate_tritri(*gen::find_tritri_family(f->name.substr(7)), kCount, kSeed));
    for (int k = 0; k < 4; ++k) {
      const verify::Stats& st = cmp.stats.at({names[k], f->name});
      const int prec = k % 2 == 0 ? 0 : 1;
      EXPECT_EQ(st.cases, std::size_t(direct.pairs[prec])) << f->name << " " << names[k];
      EXPECT_EQ(st.cases + st.unjudged, kCount) << f->name << " " << names[k];
      EXPECT_EQ(st.false_hit + st.false_miss, std::size_t(direct.wrong[k])) << f->name << " " << names[k];
      EXPECT_EQ(st.false_miss, std::size_t(direct.false_neg[k])) << f->name << " " << names[k];
      EXPECT_EQ(st.wrong_hit_class + st.wrong_class, 0u) << "coarse answers have no class";
      EXPECT_EQ(st.coarse, st.cases);
      wrong_seen += st.class_errors();
    }
  }
  EXPECT_GT(wrong_seen, 0u);  // the hard families do defeat them
}

}  // namespace
}  // namespace rayproof
