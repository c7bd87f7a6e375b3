// check_crossings (rayproof/verify/crossings_check.h): every count of the judgement equals a
// brute-force exact tally made another way (every triangle's exact class from CGAL,
// verify::exact::intersect; contacts as the triangles met at equal exact t, in GMP rationals; the
// crossings per contact from ExactMesh::ray_crossings), on a cube, a fan of six triangles meeting at
// an apex and a mesh with coincident and coplanar parts. Judged: rayproof's own crossings (no
// finding), a naive double Möller–Trumbore all-hits loop, and hand-made wrong answers (one hit
// dropped, duplicated, the order reversed, a touch added, t shifted, a triangle not met, garbage,
// hits on an invalid ray), each moving exactly its counter; another triangle of a vertex's fan
// naming the crossing there moves none.
#include <gtest/gtest.h>
#include <gmpxx.h>

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "rayproof/float_util.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/verify/crossings_check.h"
#include "rayproof/verify/crossings_gtest.h"
#include "rayproof/verify/exact.h"

namespace rayproof {
namespace {

using verify::CrossingHit;
using verify::CrossingsAnswer;
using verify::CrossingsCounts;
using Tri = std::array<std::uint32_t, 3>;

struct OwnedMesh {
  std::vector<Vec3<double>> v;
  std::vector<Tri> f;
  std::string name;
  [[nodiscard]] verify::CasterMesh view() const { return {v, f, name}; }
  [[nodiscard]] Triangle<double> tri(std::size_t k) const { return {v[f[k][0]], v[f[k][1]], v[f[k][2]]}; }
};

OwnedMesh cube() {
  OwnedMesh m{{}, {}, "cube"};
  for (int i = 0; i < 8; ++i) m.v.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  const std::uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) m.f.push_back({f[0], f[1], f[2]}), m.f.push_back({f[0], f[2], f[3]});
  return m;
}

/// A closed hexagonal pyramid: six triangles meet at the apex, six at the base's centre.
OwnedMesh fan() {
  OwnedMesh m{{{0, 0, 1}, {0, 0, 0}}, {}, "fan"};
  const double c[6][2] = {{1, 0}, {0.5, 0.875}, {-0.5, 0.875}, {-1, 0}, {-0.5, -0.875}, {0.5, -0.875}};
  for (const auto& p : c) m.v.push_back({p[0], p[1], 0});
  for (std::uint32_t k = 0; k < 6; ++k) {
    const std::uint32_t a = 2 + k, b = 2 + (k + 1) % 6;
    m.f.push_back({0, a, b});
    m.f.push_back({1, b, a});
  }
  return m;
}

/// Coincident triangles of one orientation (two crossings at one point), of opposite orientations
/// (a touch), and a square of two coplanar triangles (one crossing through their diagonal).
OwnedMesh coincident() {
  OwnedMesh m{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {0, 0, 2}, {1, 0, 2}, {1, 1, 2},
               {0, 1, 2}},
              {{0, 1, 2}, {0, 1, 2}, {3, 4, 5}, {3, 5, 4}, {6, 7, 8}, {6, 8, 9}},
              "coincident"};
  return m;
}

/// The caster judge's sets and, from three points outside, rays through every vertex and every
/// edge midpoint of the mesh (set "aimed"), and a few axis rays through the vertices.
verify::CasterRays rays_for(const OwnedMesh& m, const verify::CrossingsCheckOptions& opt) {
  verify::CasterRays r = verify::crossings_rays(m.view(), opt);
  const auto set = static_cast<std::uint8_t>(r.names.size());
  r.names.push_back("aimed");
  std::vector<Vec3<double>> targets = m.v;
  for (const Tri& t : m.f)
    for (int e = 0; e < 3; ++e) targets.push_back((m.v[t[e]] + m.v[t[(e + 1) % 3]]) * 0.5);
  for (const Vec3<double>& o : {Vec3<double>{-2.5, 0.25, 0.5}, Vec3<double>{0.3, -3, 1.75}, Vec3<double>{0.2, 0.1, 4}})
    for (const Vec3<double>& p : targets) r.rays.push_back({o, p - o}), r.set.push_back(set);
  for (const Vec3<double>& p : m.v)
    for (const Vec3<double>& d : {Vec3<double>{0, 0, -1}, Vec3<double>{1, 0, 0}})
      r.rays.push_back({p - d * 3.0, d}), r.set.push_back(set);
  if (opt.precision == verify::CasterPrecision::float32)
    for (Ray<double>& x : r.rays) x = {x.o.cast<float>().cast<double>(), x.d.cast<float>().cast<double>()};
  return r;
}

const TRange kPositive{std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::infinity()};

/// rayproof's own crossings as answers.
std::vector<CrossingsAnswer> exact_answers(const OwnedMesh& m, const verify::CasterRays& rays) {
  const ExactMesh em(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
  std::vector<CrossingsAnswer> out(rays.rays.size());
  for (std::size_t i = 0; i < rays.rays.size(); ++i)
    for (const Crossing& c : em.ray_crossings(rays.rays[i], kPositive).crossings) out[i].hits.push_back({c.t, c.triangle});
  return out;
}

/// A naive all-hits loop: Möller–Trumbore in double on every triangle, t > 0, every hit kept.
std::vector<CrossingsAnswer> naive_answers(const OwnedMesh& m, const verify::CasterRays& rays) {
  std::vector<CrossingsAnswer> out(rays.rays.size());
  for (std::size_t i = 0; i < rays.rays.size(); ++i) {
    const Ray<double>& r = rays.rays[i];
    for (std::size_t k = 0; k < m.f.size(); ++k) {
      const Triangle<double> t = m.tri(k);
      const Vec3<double> e1 = t.p1 - t.p0, e2 = t.p2 - t.p0, p = cross(r.d, e2);
      const double det = dot(e1, p);
      if (det == 0 || !std::isfinite(det)) continue;
      const Vec3<double> s = r.o - t.p0, qv = cross(s, e1);
      const double u = dot(s, p) / det, v = dot(r.d, qv) / det, tt = dot(e2, qv) / det;
      if (u >= 0 && v >= 0 && u + v <= 1 && tt > 0) out[i].hits.push_back({tt, std::int64_t(k)});
    }
    std::sort(out[i].hits.begin(), out[i].hits.end(), [](auto& a, auto& b) { return a.t < b.t; });
  }
  return out;
}

mpq_class exact_t(const Ray<double>& r, const Triangle<double>& t) {
  auto q = [](const Vec3<double>& v) { return std::array<mpq_class, 3>{v.x, v.y, v.z}; };
  const auto p0 = q(t.p0), p1 = q(t.p1), p2 = q(t.p2), o = q(r.o), d = q(r.d);
  std::array<mpq_class, 3> e1, e2, n, w;
  for (int c = 0; c < 3; ++c) e1[c] = p1[c] - p0[c], e2[c] = p2[c] - p0[c], w[c] = p0[c] - o[c];
  n = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  return mpq_class((w[0] * n[0] + w[1] * n[1] + w[2] * n[2]) / (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]));
}

/// The brute-force tally.
CrossingsCounts brute_tally(const OwnedMesh& m, const verify::CasterRays& rays, std::span<const CrossingsAnswer> answers,
                            bool float32, std::uint64_t tol) {
  const ExactMesh em(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
  CrossingsCounts c;
  for (std::size_t i = 0; i < rays.rays.size(); ++i) {
    const Ray<double>& r = rays.rays[i];
    const CrossingsAnswer& a = answers[i];
    ++c.rays;
    if (!r.valid()) {
      ++c.invalid_rays;
      c.invalid_failures += a.failed;
      c.invalid_hit += !a.failed && !a.hits.empty();
      continue;
    }
    const RayCrossings ref = em.ray_crossings(r, kPositive);
    c.crossings += ref.crossings.size();
    if (a.failed) {
      ++c.failures;
      continue;
    }
    c.hits += a.hits.size();
    for (std::size_t k = 1; k < a.hits.size(); ++k)
      if (a.hits[k].t < a.hits[k - 1].t) {
        ++c.wrong_order;
        break;
      }
    // Every triangle's exact class; the groups of those met at t > 0 by exact t.
    std::vector<TriangleHit<double>> cls(m.f.size());
    std::vector<int> group(m.f.size(), -1);
    std::vector<mpq_class> group_t;
    for (std::size_t k = 0; k < m.f.size(); ++k) {
      cls[k] = exact::intersect(r, m.tri(k));
      const Contact ct = cls[k].contact;
      if (ct != Contact::interior && ct != Contact::edge && ct != Contact::vertex) continue;
      const mpq_class t = exact_t(r, m.tri(k));
      if (t <= 0) continue;
      for (std::size_t g = 0; g < group_t.size() && group[k] < 0; ++g)
        if (group_t[g] == t) group[k] = int(g);
      if (group[k] < 0) group[k] = int(group_t.size()), group_t.push_back(t);
    }
    const std::size_t ng = group_t.size();
    std::vector<int> want(ng, 0), got(ng, 0), rep(ng, -1);
    std::vector<bool> touch(ng, false);
    for (const Crossing& x : ref.crossings) ++want[group[x.triangle]], rep[group[x.triangle]] = int(x.triangle);
    for (const Touch& x : ref.touches)
      if (x.contact != Contact::coplanar) touch[group[x.triangle]] = true;
    std::vector<int> coplanar_got(m.f.size(), 0);
    for (const CrossingHit& h : a.hits) {
      if (!std::isfinite(h.t) || h.triangle < 0 || std::size_t(h.triangle) >= m.f.size()) {
        ++c.garbage;
        continue;
      }
      const TriangleHit<double>& x = cls[h.triangle];
      if (x.contact == Contact::coplanar) {
        if (std::isnan(x.t2)) ++c.no_contact;
        else if (x.t2 == 0) ++c.at_origin;
        else ++coplanar_got[h.triangle];
        continue;
      }
      if (x.contact != Contact::interior && x.contact != Contact::edge && x.contact != Contact::vertex) {
        ++c.no_contact;
        continue;
      }
      if (exact_t(r, m.tri(h.triangle)) == 0) {
        ++c.at_origin;
        continue;
      }
      const int g = group[h.triangle];
      ++got[g];
      if (want[g] == 0) continue;
      const double rounded = exact::intersect(r, m.tri(rep[g])).t;
      const std::uint64_t u =
          float32 ? ulp_distance(float(h.t), float(rounded)) : ulp_distance(h.t, rounded);
      c.max_ulps = std::max(c.max_ulps, u);
      c.t_over_tolerance += u > tol;
    }
    for (std::size_t g = 0; g < ng; ++g) {
      if (want[g] > 0) {
        if (got[g] < want[g]) c.missing += want[g] - got[g];
        else c.duplicates += got[g] - want[g];
      } else if (got[g] > 0) {
        EXPECT_TRUE(touch[g]) << "a contact neither crossed nor touched";
        ++c.touch_hits, c.duplicates += got[g] - 1;
      }
    }
    for (int n : coplanar_got)
      if (n > 0) ++c.touch_hits, c.duplicates += n - 1;
  }
  return c;
}

void expect_counts(const CrossingsCounts& got, const CrossingsCounts& want, const std::string& what) {
  for (const verify::CrossingsCounter& counter : verify::kCrossingsCounters)
    EXPECT_EQ(verify::count_of(got, counter), verify::count_of(want, counter)) << what << ": " << counter.key;
}

struct Case {
  OwnedMesh mesh;
  verify::CrossingsCheckOptions opt;
  verify::CasterRays rays;
  std::vector<CrossingsAnswer> exact;
};

Case make_case(OwnedMesh m, verify::CasterPrecision p = verify::CasterPrecision::float64) {
  Case c{std::move(m), {}, {}, {}};
  c.opt.precision = p;
  c.opt.random_rays = 200;
  c.opt.threads = 2;
  c.rays = rays_for(c.mesh, c.opt);
  c.exact = exact_answers(c.mesh, c.rays);
  return c;
}

verify::CrossingsTally judge(const Case& c, std::span<const CrossingsAnswer> answers) {
  return verify::CrossingsJudge(c.mesh.view()).judge(c.rays, answers, c.opt);
}

TEST(CrossingsCheck, OwnCrossingsAndNaiveLoopMatchTheBruteForce) {
  for (OwnedMesh m : {cube(), fan(), coincident()}) {
    for (auto p : {verify::CasterPrecision::float64, verify::CasterPrecision::float32}) {
      const Case c = make_case(m, p);
      const bool f32 = p == verify::CasterPrecision::float32;
      const verify::CrossingsTally own = judge(c, c.exact);
      EXPECT_EQ(own.findings(), 0u) << m.name << (own.reproducers.empty() ? "" : "\n" + own.reproducers[0].line);
      expect_counts(own, brute_tally(c.mesh, c.rays, c.exact, f32, 1), m.name + " own");
      EXPECT_GT(own.crossings, 100u) << m.name;
      const auto naive = naive_answers(c.mesh, c.rays);
      const verify::CrossingsTally t = judge(c, naive);
      expect_counts(t, brute_tally(c.mesh, c.rays, naive, f32, 1), m.name + " naive");
      EXPECT_GT(t.findings(), 0u) << m.name;
      if (f32) continue;
      std::uint64_t with = 0;  // the rays with a finding, from the brute force ray by ray
      for (std::size_t i = 0; i < c.rays.rays.size(); ++i) {
        const verify::CasterRays one{{c.rays.rays[i]}, {0}, {"one"}, {}};
        with += brute_tally(c.mesh, one, std::span(naive).subspan(i, 1), f32, 1).findings() > 0;
      }
      EXPECT_EQ(t.rays_with_findings, with) << m.name;
      if (m.name != "coincident") {
        EXPECT_GT(t.duplicates + t.missing, 0u) << m.name;  // shared edges and vertices
      }
    }
  }
}

/// The first valid ray i (in the "aimed" set when asked) for which pick(i) holds.
template <class Pick>
std::size_t find_ray(const Case& c, Pick&& pick) {
  for (std::size_t i = 0; i < c.rays.rays.size(); ++i)
    if (c.rays.rays[i].valid() && pick(i)) return i;
  ADD_FAILURE() << "no such ray";
  return 0;
}

TEST(CrossingsCheck, EachWrongAnswerMovesItsCounter) {
  for (OwnedMesh m : {cube(), fan(), coincident()}) {
    const Case c = make_case(m);
    const ExactMesh em(VertexArray(&c.mesh.v[0].x, c.mesh.v.size()), IndexArray{c.mesh.f[0].data(), c.mesh.f.size()});
    const CrossingsCounts base = judge(c, c.exact);
    ASSERT_EQ(base.findings(), 0u) << m.name;
    auto check = [&](const std::string& what, std::size_t i, auto&& edit, std::uint64_t CrossingsCounts::*counter,
                     std::uint64_t by) {
      std::vector<CrossingsAnswer> a = c.exact;
      edit(a[i].hits);
      const verify::CrossingsTally t = judge(c, a);
      CrossingsCounts want = base;
      if (counter) want.*counter += by;
      if (c.rays.rays[i].valid()) want.hits = base.hits - c.exact[i].hits.size() + a[i].hits.size();
      want.max_ulps = t.max_ulps;  // checked by the brute force below
      expect_counts(t, want, m.name + " " + what);
      expect_counts(t, brute_tally(c.mesh, c.rays, a, false, 1), m.name + " " + what + " (brute force)");
      if (counter) {
        ASSERT_FALSE(t.reproducers.empty()) << what;
        EXPECT_EQ(t.reproducers[0].ray, i) << what;
      }
    };
    const std::size_t two = find_ray(c, [&](std::size_t i) {
      return c.exact[i].hits.size() >= 2 && c.exact[i].hits.front().t < c.exact[i].hits.back().t;
    });
    check("drop", two, [](auto& h) { h.erase(h.begin()); }, &CrossingsCounts::missing, 1);
    check("duplicate", two, [](auto& h) { h.insert(h.begin(), h.front()); }, &CrossingsCounts::duplicates, 1);
    check("reverse", two, [](auto& h) { std::reverse(h.begin(), h.end()); }, &CrossingsCounts::wrong_order, 1);
    check("shift t", two, [](auto& h) { h.back().t = next_up(next_up(next_up(h.back().t))); },
          &CrossingsCounts::t_over_tolerance, 1);
    check("t correctly rounded", two, [&](auto& h) { h.back().t = exact::intersect(c.rays.rays[two], c.mesh.tri(h.back().triangle)).t; },
          nullptr, 0);
    check("garbage", two, [](auto& h) { h.push_back({kNaN<double>, 0}); }, &CrossingsCounts::garbage, 1);
    check("out of range", two, [&](auto& h) { h.push_back({h.back().t, std::int64_t(c.mesh.f.size())}); },
          &CrossingsCounts::garbage, 1);
    // Two sheets crossed at one point (the coincident triangles of one orientation): both hits dropped.
    if (m.name == "coincident") {
      const std::size_t twice = find_ray(c, [&](std::size_t i) {
        const auto& h = c.exact[i].hits;
        return h.size() == 2 && h[0].t == h[1].t && h[0].triangle == h[1].triangle;
      });
      check("drop both of a double crossing", twice, [](auto& h) { h.clear(); }, &CrossingsCounts::missing, 2);
      check("the other coincident triangle names one", twice, [](auto& h) { h[0].triangle = 1 - h[0].triangle; },
            nullptr, 0);
    }
    // A triangle the ray does not meet.
    const std::uint64_t unmet = [&] {
      for (std::size_t k = 0; k < c.mesh.f.size(); ++k) {
        const Contact x = exact::intersect(c.rays.rays[two], c.mesh.tri(k)).contact;
        if (x == Contact::miss || x == Contact::behind || x == Contact::parallel) return k;
      }
      return c.mesh.f.size();
    }();
    if (unmet < c.mesh.f.size())
      check("no contact", two, [&](auto& h) { h.push_back({h.back().t * 2, std::int64_t(unmet)}); },
            &CrossingsCounts::no_contact, 1);
    // A touch reported: a point touch with its t.
    const std::size_t touched = find_ray(c, [&](std::size_t i) {
      const RayCrossings x = em.ray_crossings(c.rays.rays[i], kPositive);
      return std::any_of(x.touches.begin(), x.touches.end(), [](const Touch& t) { return t.contact != Contact::coplanar; });
    });
    check("touch", touched, [&](auto& h) {
      for (const Touch& t : em.ray_crossings(c.rays.rays[touched], kPositive).touches)
        if (t.contact != Contact::coplanar) {
          h.push_back({t.t, t.triangle});
          break;
        }
      std::sort(h.begin(), h.end(), [](auto& a, auto& b) { return a.t < b.t; });
    }, &CrossingsCounts::touch_hits, 1);
    // Another triangle meeting the ray at a crossing's point names it: right.
    std::int64_t other = -1;
    const std::size_t shared = find_ray(c, [&](std::size_t i) {
      for (const CrossingHit& h : c.exact[i].hits)
        for (std::size_t k = 0; k < c.mesh.f.size(); ++k) {
          if (std::int64_t(k) == h.triangle) continue;
          const Contact x = exact::intersect(c.rays.rays[i], c.mesh.tri(k)).contact;
          if ((x == Contact::edge || x == Contact::vertex || x == Contact::interior) &&
              exact_t(c.rays.rays[i], c.mesh.tri(k)) == exact_t(c.rays.rays[i], c.mesh.tri(h.triangle))) {
            other = std::int64_t(k);
            return true;
          }
        }
      return false;
    });
    check("other triangle of the contact", shared, [&](auto& h) {
      for (CrossingHit& x : h)
        if (exact_t(c.rays.rays[shared], c.mesh.tri(x.triangle)) == exact_t(c.rays.rays[shared], c.mesh.tri(other))) {
          x.triangle = other;
          break;
        }
    }, nullptr, 0);
    // Hits answered to an invalid ray.
    const std::size_t invalid = [&] {
      for (std::size_t i = 0; i < c.rays.rays.size(); ++i)
        if (!c.rays.rays[i].valid()) return i;
      return std::size_t(0);
    }();
    ASSERT_FALSE(c.rays.rays[invalid].valid());
    check("invalid", invalid, [](auto& h) { h.push_back({1.0, 0}); }, &CrossingsCounts::invalid_hit, 1);
  }
}

TEST(CrossingsCheck, FunctionsRunBatchByBatch) {
  const OwnedMesh m = cube();
  const ExactMesh em(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
  std::size_t calls = 0;
  auto own = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d,
                 std::span<std::vector<CrossingHit>> out) {
    ++calls;
    for (std::size_t i = 0; i < o.size(); ++i)
      for (const Crossing& c : em.ray_crossings({o[i], d[i]}, kPositive).crossings) out[i].push_back({c.t, c.triangle});
  };
  verify::CrossingsCheckOptions opt;
  opt.random_rays = 100;
  opt.batch = 64;
  const verify::CrossingsTally t = verify::check_crossings(own, m.view(), opt);
  EXPECT_EQ(t.findings(), 0u);
  EXPECT_GT(calls, t.rays / 64);
  EXPECT_NE(verify::summary_text(t).find("cost:"), std::string::npos);
  // A function that throws fails its batches' rays (valid and invalid) and keeps the message.
  auto thrower = [](std::span<const Vec3<double>>, std::span<const Vec3<double>>, std::span<std::vector<CrossingHit>>) {
    throw std::runtime_error("no crossings today");
  };
  const verify::CrossingsTally f = verify::check_crossings(thrower, m.view(), opt);
  EXPECT_EQ(f.failures + f.invalid_failures, f.rays);
  EXPECT_EQ(f.missing, 0u);
  ASSERT_FALSE(f.notes.empty());
  EXPECT_NE(f.notes.back().find("no crossings today"), std::string::npos);
  // Rays given: the set "user".
  const std::vector<Ray<double>> rays{{{0.5, 0.5, -1}, {0, 0, 1}}, {{0, 0, -1}, {0, 0, 1}}};
  const verify::CrossingsTally u = verify::check_crossings(own, m.view(), rays, opt);
  EXPECT_EQ(u.rays, 2u);
  EXPECT_EQ(u.crossings, 4u);
  ASSERT_EQ(u.sets.size(), 1u);
  EXPECT_EQ(u.sets[0].set, "user");
}

TEST(CrossingsCheck, GtestMacroPassesOwnAndFailsADroppedHit) {
  const OwnedMesh m = fan();
  const ExactMesh em(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()});
  auto own = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d,
                 std::span<std::vector<CrossingHit>> out) {
    for (std::size_t i = 0; i < o.size(); ++i)
      for (const Crossing& c : em.ray_crossings({o[i], d[i]}, kPositive).crossings) out[i].push_back({c.t, c.triangle});
  };
  EXPECT_CROSSINGS_MATCH_EXACT(own, m.view());
  auto last_dropped = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d,
                          std::span<std::vector<CrossingHit>> out) {
    own(o, d, out);
    for (auto& h : out)
      if (!h.empty()) h.pop_back();
  };
  const ::testing::AssertionResult r = gtest::crossings_match_exact(last_dropped, m.view());
  EXPECT_FALSE(r);
  EXPECT_NE(std::string(r.message()).find("missing "), std::string::npos) << r.message();
}

}  // namespace
}  // namespace rayproof
