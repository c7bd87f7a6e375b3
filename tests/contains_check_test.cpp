// check_contains (rayproof/verify/contains_check.h): rayproof's own contains gets no finding; a
// float ray-parity test, a function inverted on a known subset, one that throws and one that
// returns garbage get exactly the counts of a brute-force tally, whose sides come from the
// generalized winding number over every triangle (winding_brute_force, MPFR where it cannot tell),
// not from the judge's ExactMesh.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/winding.h"
#include "rayproof/verify/contains_check.h"
#include "rayproof/verify/contains_gtest.h"

namespace rayproof {
namespace {

using verify::ContainsAnswer;
using verify::ContainsCounts;
using verify::ContainsTally;
using Tri = std::array<std::uint32_t, 3>;

struct OwnedMesh {
  std::vector<Vec3<double>> v;
  std::vector<Tri> f;
  std::string name;
  [[nodiscard]] verify::ContainsMesh view() const { return {v, f, name}; }
};

/// The unit cube shifted by `dx`, outward, appended to m.
void add_cube(OwnedMesh& m, double dx, bool top = true) {
  const auto base = static_cast<std::uint32_t>(m.v.size());
  for (int i = 0; i < 8; ++i) m.v.push_back({double(i & 1) + dx, double((i >> 1) & 1), double((i >> 2) & 1)});
  const std::uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (int k = 0; k < 6; ++k) {
    if (!top && k == 1) continue;  // the face z = 1
    m.f.push_back({base + q[k][0], base + q[k][1], base + q[k][2]});
    m.f.push_back({base + q[k][0], base + q[k][2], base + q[k][3]});
  }
}

OwnedMesh cube() {
  OwnedMesh m{{}, {}, "cube"};
  add_cube(m, 0);
  return m;
}
OwnedMesh open_box() {
  OwnedMesh m{{}, {}, "open-box"};
  add_cube(m, 0, false);
  return m;
}
/// Two cubes overlapping in x in [0.5, 1]: winding number 2 there (inside by nonzero, outside by parity).
OwnedMesh overlap() {
  OwnedMesh m{{}, {}, "two-cubes"};
  add_cube(m, 0);
  add_cube(m, 0.5);
  return m;
}
OwnedMesh tetrahedron() {
  OwnedMesh m{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.25, 1e-3}}, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}},
              "thin-tetrahedron"};
  return m;
}

bool finite(const Vec3<double>& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

/// The brute-force side: the generalized winding number over every triangle, in double with its
/// bound, then MPFR at 1024 bits where the bound straddles the rule's threshold.
struct BruteSide {
  bool invalid = false, surface = false;
  std::int32_t winding = 0;  ///< closed meshes: the integer nearest w
  double w = 0;
  bool near_half = false;  ///< |w - 1/2| within the double evaluation's bound
};

BruteSide brute(const OwnedMesh& m, const Vec3<double>& p) {
  BruteSide s;
  if (!finite(p)) return s.invalid = true, s;
  WindingValue w = winding_brute_force(m.v, m.f, p);
  if (w.surface) return s.surface = true, s;
  s.near_half = std::fabs(w.w - 0.5) <= w.bound;
  if (s.near_half) w = winding_brute_force_mpfr(m.v, m.f, p, 1024);
  s.w = w.w;
  s.winding = static_cast<std::int32_t>(std::lround(w.w));
  return s;
}

/// The brute-force tally of answers under a rule (closed: oriented meshes only, as the tests use).
ContainsCounts brute_tally(const OwnedMesh& m, bool closed, ContainsRule rule, const verify::ContainsPoints& pts,
                           std::span<const ContainsAnswer> answers) {
  ContainsCounts c;
  for (std::size_t i = 0; i < pts.points.size(); ++i) {
    const BruteSide s = brute(m, pts.points[i]);
    const ContainsAnswer& a = answers[i];
    const bool readable = !a.failed && a.side >= 0 && a.side <= 2;
    ++c.points;
    if (s.invalid) {
      ++c.invalid_points;
      if (a.failed) ++c.invalid_failures;
      else if (!readable) ++c.garbage;
      else if (a.side == 1) ++c.invalid_said_inside;
      else if (a.side == 2) ++c.invalid_said_surface;
      continue;
    }
    bool inside = false, differ = false;
    if (!s.surface) {
      if (closed) {
        const bool nonzero = s.winding != 0, parity = (s.winding & 1) != 0;
        differ = nonzero != parity;
        inside = rule == ContainsRule::parity ? parity : rule == ContainsRule::winding ? s.winding >= 1 : nonzero;
      } else {
        inside = s.w > 0.5;
      }
    }
    if (inside) ++c.inside;
    if (s.surface) ++c.surface;
    if (differ) ++c.rules_differ;
    if (a.failed) {
      ++c.failures;
      continue;
    }
    if (!readable) {
      ++c.garbage;
      continue;
    }
    if (s.surface) {
      ++(a.side == 0 ? c.surface_said_outside : a.side == 1 ? c.surface_said_inside : c.surface_said_surface);
      continue;
    }
    if (a.side == 2) {
      ++c.false_surface;
      continue;
    }
    if ((a.side == 1) == inside) continue;
    if (differ) {
      ++c.rules_differ_other;
      if (rule == ContainsRule::automatic) continue;
    }
    if (!closed && s.near_half) {
      ++c.winding_near_half;
      continue;
    }
    ++(inside ? c.inside_called_outside : c.outside_called_inside);
  }
  return c;
}

void expect_counts_equal(const ContainsCounts& got, const ContainsCounts& want, const std::string& what) {
  for (const verify::ContainsCounter& counter : verify::kContainsCounters)
    EXPECT_EQ(verify::count_of(got, counter), verify::count_of(want, counter)) << what << ": " << counter.key;
}

/// rayproof's own contains, surface as 2.
verify::ContainsFunction exact_function(const ExactMesh& mesh) {
  return [&mesh](std::span<const Vec3<double>> p, std::span<std::int32_t> out) {
    std::vector<Side> s(p.size());
    mesh.contains(p, s, 1);
    for (std::size_t i = 0; i < p.size(); ++i) out[i] = s[i] == Side::invalid ? 0 : static_cast<std::int32_t>(s[i]);
  };
}

/// A float-free but naive test: crossings of the ray along +x, counted with closed barycentric
/// tests in double (a ray through an edge or vertex counts every triangle there).
verify::ContainsFunction naive_parity(const OwnedMesh& m) {
  return [&m](std::span<const Vec3<double>> p, std::span<std::int32_t> out) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      int count = 0;
      for (const Tri& t : m.f) {
        const Vec3<double> a = m.v[t[0]], b = m.v[t[1]], c = m.v[t[2]];
        // Project on (y, z): is (p.y, p.z) in the closed triangle?
        auto o = [](double ay, double az, double by, double bz, double py, double pz) {
          return (by - ay) * (pz - az) - (bz - az) * (py - ay);
        };
        const double d = o(a.y, a.z, b.y, b.z, c.y, c.z);
        if (d == 0) continue;
        const double u = o(b.y, b.z, c.y, c.z, p[i].y, p[i].z) / d, v = o(c.y, c.z, a.y, a.z, p[i].y, p[i].z) / d,
                     w = 1 - u - v;
        if (u < 0 || v < 0 || w < 0) continue;
        const double x = u * a.x + v * b.x + w * c.x;
        if (x > p[i].x) ++count;
      }
      out[i] = count & 1;
    }
  };
}

struct Judged {
  verify::ContainsPoints points;
  std::vector<ContainsAnswer> answers;
  ContainsTally tally;
};

Judged run(const OwnedMesh& m, const verify::ContainsFunction& fn, verify::ContainsCheckOptions opt = {}) {
  opt.random_points = 300;
  opt.max_points_per_set = 300;
  Judged r;
  r.points = verify::contains_points(m.view(), opt);
  r.answers.resize(r.points.points.size());
  std::string error;
  verify::run_contains(fn, r.points.points, opt.batch, r.answers, error);
  r.tally = verify::ContainsJudge(m.view(), opt.rule).judge(r.points, r.answers, opt);
  return r;
}

TEST(ContainsCheck, ExactFunctionHasNoFindingOnAnyMesh) {
  for (const OwnedMesh& m : {cube(), tetrahedron(), open_box(), overlap()}) {
    const ExactMesh mesh(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
    const Judged r = run(m, exact_function(mesh));
    EXPECT_EQ(r.tally.findings(), 0u) << m.name << "\n" << verify::summary_text(r.tally);
    EXPECT_EQ(r.tally.surface_said_surface, r.tally.surface) << m.name;
    EXPECT_GT(r.tally.surface, 0u) << m.name;
    EXPECT_GT(r.tally.inside, 0u) << m.name;
    EXPECT_EQ(r.tally.invalid_points, 10u) << m.name;
    EXPECT_EQ(r.tally.sets.size(), 9u) << m.name;
    EXPECT_GT(r.tally.contains_seconds, 0) << m.name;
    const bool closed = m.name != "open-box";
    expect_counts_equal(r.tally, brute_tally(m, closed, ContainsRule::automatic, r.points, r.answers), m.name);
  }
}

TEST(ContainsCheck, SurfaceSetsLieOnTheSurfaceAndNudgedAndMedialPointsOff) {
  const OwnedMesh m = cube();
  verify::ContainsCheckOptions opt;
  const auto pts = verify::contains_points(m.view(), opt);
  std::size_t medial = 0, medial_inside = 0;
  for (std::size_t i = 0; i < pts.points.size(); ++i) {
    const std::string& set = pts.names[pts.set[i]];
    const BruteSide s = brute(m, pts.points[i]);
    if (set == "vertex" || set == "edge" || set == "face") {
      EXPECT_TRUE(s.surface) << set << " " << i;  // the cube's midpoints and centroids are exact in binary
    } else if (set == "nudged") {
      EXPECT_FALSE(s.surface) << i;
    } else if (set == "invalid") {
      EXPECT_TRUE(s.invalid) << i;
    } else if (set == "medial") {
      EXPECT_FALSE(s.surface) << i;  // off every edge along its bisector, as many inside as out
      ++medial, medial_inside += s.winding != 0 ? 1 : 0;
    }
  }
  EXPECT_EQ(medial, 18u * 6u);  // the cube's 18 edges, 3 distances both ways
  EXPECT_EQ(2 * medial_inside, medial);
}

// precision float32: every point is a float (the nudges are float ulps: off the cube's surface),
// and the counts still equal the brute-force tally.
TEST(ContainsCheck, FloatPrecisionGivesFloatPointsNudgedByFloatUlps) {
  const OwnedMesh m = cube();
  verify::ContainsCheckOptions opt;
  opt.precision = verify::ContainsPrecision::float32;
  const auto pts = verify::contains_points(m.view(), opt);
  std::size_t nudged = 0;
  for (std::size_t i = 0; i < pts.points.size(); ++i) {
    const Vec3<double>& p = pts.points[i];
    const bool is_float = (std::isnan(p.x) || double(float(p.x)) == p.x) && (std::isnan(p.y) || double(float(p.y)) == p.y) &&
                          (std::isnan(p.z) || double(float(p.z)) == p.z);
    EXPECT_TRUE(is_float) << i;
    if (pts.names[pts.set[i]] != "nudged") continue;
    ++nudged;
    EXPECT_FALSE(brute(m, p).surface) << i;  // a float ulp off, and still a float (above)
  }
  EXPECT_GT(nudged, 0u);
  const ExactMesh mesh(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
  const Judged exact = run(m, exact_function(mesh), opt);
  EXPECT_EQ(exact.tally.findings(), 0u) << verify::summary_text(exact.tally);
  const Judged naive = run(m, naive_parity(m), opt);
  expect_counts_equal(naive.tally, brute_tally(m, true, ContainsRule::automatic, naive.points, naive.answers), "float");
}

TEST(ContainsCheck, NaiveParityCountsEqualTheBruteForceTally) {
  for (const OwnedMesh& m : {cube(), tetrahedron(), overlap()}) {
    const Judged r = run(m, naive_parity(m));
    expect_counts_equal(r.tally, brute_tally(m, true, ContainsRule::automatic, r.points, r.answers), m.name);
    EXPECT_GT(r.tally.findings(), 0u) << m.name << "\n" << verify::summary_text(r.tally);
    ASSERT_FALSE(r.tally.reproducers.empty());
    const std::string& line = r.tally.reproducers.front().line;
    EXPECT_NE(line.find("mesh=" + m.name + " point "), std::string::npos) << line;
    EXPECT_NE(line.find(" exact: "), std::string::npos) << line;
    EXPECT_NE(line.find(" answer: "), std::string::npos) << line;
  }
}

// A function inverted on every 7th point, answering 2 on every 11th, garbage on every 13th and
// throwing on its third batch: exactly the brute-force counts, on every mesh and rule.
TEST(ContainsCheck, WrongOnAKnownSubsetGetsExactlyTheExpectedCounts) {
  struct Case {
    OwnedMesh m;
    bool closed;
    ContainsRule rule;
  };
  for (const Case& c : {Case{cube(), true, ContainsRule::automatic}, Case{tetrahedron(), true, ContainsRule::winding},
                        Case{open_box(), false, ContainsRule::automatic}, Case{overlap(), true, ContainsRule::automatic},
                        Case{overlap(), true, ContainsRule::parity}, Case{overlap(), true, ContainsRule::nonzero}}) {
    const ExactMesh mesh(VertexArray(&c.m.v[0].x, c.m.v.size()), IndexArray{c.m.f[0].data(), c.m.f.size()}, c.rule);
    std::size_t offset = 0, batches = 0;
    const verify::ContainsFunction exact = exact_function(mesh);
    const verify::ContainsFunction wrong = [&](std::span<const Vec3<double>> p, std::span<std::int32_t> out) {
      if (batches++ == 2) {
        offset += p.size();
        throw std::runtime_error("third batch");
      }
      exact(p, out);
      for (std::size_t k = 0; k < p.size(); ++k) {
        const std::size_t i = offset + k;
        if (i % 13 == 0) out[k] = 5;
        else if (i % 11 == 0) out[k] = 2;
        else if (i % 7 == 0) out[k] = out[k] == 1 ? 0 : 1;
      }
      offset += p.size();
    };
    verify::ContainsCheckOptions opt;
    opt.rule = c.rule;
    opt.batch = 97;
    const Judged r = run(c.m, wrong, opt);
    const std::string what = c.m.name + " rule " + to_string(c.rule);
    expect_counts_equal(r.tally, brute_tally(c.m, c.closed, c.rule, r.points, r.answers), what);
    EXPECT_EQ(r.tally.failures + r.tally.invalid_failures, 97u) << what;
    EXPECT_GT(r.tally.garbage, 0u) << what;
    EXPECT_GT(r.tally.false_surface, 0u) << what;
    EXPECT_GT(r.tally.inside_called_outside + r.tally.outside_called_inside, 0u) << what;
    if (c.m.name == "two-cubes") {
      EXPECT_GT(r.tally.rules_differ, 0u) << what;
      // The exact function answers nonzero: under parity its answers where the rules differ are findings.
      if (c.rule == ContainsRule::parity) {
        EXPECT_GT(r.tally.rules_differ_other, 0u) << what;
      }
    }
  }
}

TEST(ContainsCheck, OtherRuleIsReportedApartUnderAutomaticAndAFindingWhenNamed) {
  const OwnedMesh m = overlap();
  const ExactMesh parity(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()},
                         ContainsRule::parity);
  const Judged automatic = run(m, exact_function(parity));
  EXPECT_EQ(automatic.tally.findings(), 0u) << verify::summary_text(automatic.tally);
  EXPECT_GT(automatic.tally.rules_differ, 0u);
  EXPECT_EQ(automatic.tally.rules_differ_other, automatic.tally.rules_differ);
  verify::ContainsCheckOptions opt;
  opt.rule = ContainsRule::nonzero;
  const Judged named = run(m, exact_function(parity), opt);
  EXPECT_EQ(named.tally.findings(), named.tally.rules_differ);
  EXPECT_EQ(named.tally.inside_called_outside, named.tally.rules_differ);
  opt.rule = ContainsRule::parity;
  EXPECT_EQ(run(m, exact_function(parity), opt).tally.findings(), 0u);
}

TEST(ContainsCheck, NearHalfOnAnOpenMeshIsReportedApart) {
  // The open box's opening: w = 1/2 exactly on its plane inside the rim (answered outside by the rule).
  const OwnedMesh m = open_box();
  const std::vector<Vec3<double>> pts{{0.5, 0.5, 1}, {0.25, 0.75, 1}, {0.5, 0.5, 0.5}, {0.5, 0.5, 2}};
  const auto inside = [](std::span<const Vec3<double>> p, std::span<std::int32_t> out) {
    for (std::size_t i = 0; i < p.size(); ++i) out[i] = 1;
  };
  const ContainsTally t = verify::check_contains(inside, m.view(), pts);
  EXPECT_EQ(t.winding_near_half, 2u) << verify::summary_text(t);
  EXPECT_EQ(t.outside_called_inside, 1u) << verify::summary_text(t);  // (0.5, 0.5, 2): w near 0.1
  EXPECT_EQ(t.inside, 1u);
  EXPECT_EQ(t.findings(), 1u);
  EXPECT_EQ(t.rule, ContainsRule::winding);
}

TEST(ContainsCheck, ThrowingOnInvalidPointsAndBadOptions) {
  const OwnedMesh m = cube();
  const ExactMesh mesh(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
  const verify::ContainsFunction exact = exact_function(mesh);
  const verify::ContainsFunction nan_hater = [&](std::span<const Vec3<double>> p, std::span<std::int32_t> out) {
    for (const auto& q : p)
      if (!finite(q)) throw std::domain_error("NaN point");
    exact(p, out);
  };
  verify::ContainsCheckOptions opt;
  opt.batch = 1;
  opt.sets = {"random", "invalid"};
  opt.random_points = 50;
  const ContainsTally t = verify::check_contains(nan_hater, m.view(), opt);
  EXPECT_EQ(t.points, 60u);
  EXPECT_EQ(t.invalid_failures, 10u);
  EXPECT_EQ(t.findings(), 10u);
  ASSERT_FALSE(t.notes.empty());
  EXPECT_NE(t.notes.back().find("NaN point"), std::string::npos);
  EXPECT_NE(t.reproducers.front().line.find("invalid-point-failure set=invalid mesh=cube point nan"), std::string::npos)
      << t.reproducers.front().line;
  opt.sets = {"nope"};
  EXPECT_THROW((void)verify::check_contains(exact, m.view(), opt), std::invalid_argument);
  opt.sets = {};
  opt.rule = ContainsRule::nonzero;
  EXPECT_THROW((void)verify::check_contains(exact, open_box().view(), opt), MeshNotClosedError);
  // An empty mesh: everything outside.
  const OwnedMesh empty{{}, {}, "empty"};
  const auto outside = [](std::span<const Vec3<double>>, std::span<std::int32_t> out) {
    std::fill(out.begin(), out.end(), 0);
  };
  const ContainsTally e = verify::check_contains(outside, empty.view(), verify::ContainsCheckOptions{});
  EXPECT_EQ(e.findings(), 0u) << verify::summary_text(e);
  EXPECT_GT(e.points, 0u);
}

TEST(ContainsCheck, GoogleTestMacroPassesTheExactFunctionAndExplainsAWrongOne) {
  const OwnedMesh m = tetrahedron();
  const ExactMesh mesh(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
  EXPECT_CONTAINS_MATCHES_EXACT(exact_function(mesh), m.view());
  const ::testing::AssertionResult wrong = gtest::contains_matches_exact(naive_parity(m), m.view());
  EXPECT_FALSE(wrong);
  EXPECT_NE(std::string(wrong.message()).find(" mesh=thin-tetrahedron point "), std::string::npos) << wrong.message();
}

TEST(ContainsCheck, ReproducerPrintsThePointExactly) {
  const OwnedMesh m = cube();
  const Vec3<double> p{std::nextafter(1.0, 2.0), 0.5, 0.1};  // one ulp outside the face x = 1
  const auto inside = [](std::span<const Vec3<double>> q, std::span<std::int32_t> out) {
    for (std::size_t i = 0; i < q.size(); ++i) out[i] = 1;
  };
  const ContainsTally t = verify::check_contains(inside, m.view(), std::span<const Vec3<double>>(&p, 1));
  ASSERT_EQ(t.reproducers.size(), 1u);
  EXPECT_EQ(t.reproducers[0].line,
            "outside-called-inside set=user mesh=cube point 1.0000000000000002 0.5 0.1 exact: outside (winding number 0, "
            "rule nonzero) answer: 1");
  EXPECT_NE(verify::summary_text(t).find("cost: judging"), std::string::npos);
}

}  // namespace
}  // namespace rayproof
