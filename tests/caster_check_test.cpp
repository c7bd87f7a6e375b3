// check_caster (rayproof/verify/caster_check.h): exact casters pass, a strict-barycentric float
// caster and a garbage caster are caught, and on small meshes every count equals a brute-force
// exact tally over every triangle of the same rays and answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <stdexcept>
#include <type_traits>

#include "rayproof/scene/mesh_caster.h"
#include "rayproof/verify/caster_check.h"
#include "rayproof/verify/caster_gtest.h"
#include "rayproof/verify/exact.h"
#include "verify/mesh_fuzz.h"

namespace rayproof {
namespace {

using verify::CasterAnswer;
using verify::CasterTally;
using verify::CasterMesh;
using Tri = std::array<std::uint32_t, 3>;
constexpr double kInf = std::numeric_limits<double>::infinity();

struct OwnedMesh {
  std::vector<Vec3<double>> v;
  std::vector<Tri> f;
  std::string name;
  [[nodiscard]] CasterMesh view() const { return {v, f, name}; }
};

OwnedMesh cube() {
  OwnedMesh m{{}, {}, "cube"};
  for (int i = 0; i < 8; ++i) m.v.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  // Two triangles per face, outward.
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) {
    m.f.push_back({Tri::value_type(f[0]), Tri::value_type(f[1]), Tri::value_type(f[2])});
    m.f.push_back({Tri::value_type(f[0]), Tri::value_type(f[2]), Tri::value_type(f[3])});
  }
  return m;
}

OwnedMesh from(const mesh::Mesh& mm, std::string name) { return {mm.vertices, mm.triangles, std::move(name)}; }

OwnedMesh star(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec3<double>> interior;
  return from(verify::random_star_mesh(rng, 1, 1, interior), "star");
}

OwnedMesh hull(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec3<double>> interior;
  return from(verify::random_hull_mesh(rng, 12, 1, interior), "hull");
}

Triangle<double> tri_of(const OwnedMesh& m, std::size_t k) { return {m.v[m.f[k][0]], m.v[m.f[k][1]], m.v[m.f[k][2]]}; }

/// The first exact crossing at t > 0 (interior/edge/vertex t > 0, or a coplanar range reaching t > 0),
/// ties to the lowest triangle number, by brute force over every triangle.
struct Brute {
  std::int64_t tri = -1;
  double t = kInf;  // correctly rounded (a coplanar range: its start)
  bool coplanar = false;
};

bool crossing(const TriangleHit<double>& h, double& t, bool& coplanar) {
  coplanar = h.contact == Contact::coplanar;
  if (h.contact == Contact::interior || h.contact == Contact::edge || h.contact == Contact::vertex) {
    t = h.t;
    return h.t > 0;
  }
  if (coplanar && h.t > 0) {  // a range starting at the origin is an origin contact
    t = h.t;
    return true;
  }
  return false;
}

bool origin_contact(const TriangleHit<double>& h) {
  const bool point = h.contact == Contact::interior || h.contact == Contact::edge || h.contact == Contact::vertex;
  return (point || h.contact == Contact::coplanar) && h.t == 0;
}

Brute brute_closest(const OwnedMesh& m, const Ray<double>& r) {
  Brute b;
  for (std::size_t k = 0; k < m.f.size(); ++k) {
    double t;
    bool cop;
    if (crossing(exact::intersect(r, tri_of(m, k)), t, cop) && t < b.t) b = {std::int64_t(k), t, cop};
  }
  return b;
}

/// The exact caster: brute force over every triangle, exact arithmetic.
verify::ClosestCaster exact_brute_caster(const OwnedMesh& m) {
  return [&m](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d, std::span<double> t,
              std::span<std::int64_t> tri) {
    for (std::size_t i = 0; i < o.size(); ++i) {
      const Brute b = brute_closest(m, {o[i], d[i]});
      t[i] = b.t, tri[i] = b.tri;
    }
  };
}

/// Möller–Trumbore in float over every triangle with strict barycentric tests (u > 0, v > 0,
/// u + v < 1): rays through edges and vertices slip through.
verify::ClosestCaster strict_float_caster(const OwnedMesh& m) {
  return [&m](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d, std::span<double> t,
              std::span<std::int64_t> tri) {
    for (std::size_t i = 0; i < o.size(); ++i) {
      const Vec3<float> of = o[i].cast<float>(), df = d[i].cast<float>();
      float best = std::numeric_limits<float>::infinity();
      std::int64_t bt = -1;
      for (std::size_t k = 0; k < m.f.size(); ++k) {
        const Vec3<float> p0 = m.v[m.f[k][0]].cast<float>(), p1 = m.v[m.f[k][1]].cast<float>(),
                          p2 = m.v[m.f[k][2]].cast<float>();
        const Vec3<float> e1 = p1 - p0, e2 = p2 - p0, p = cross(df, e2);
        const float det = dot(e1, p);
        if (det == 0) continue;
        const float inv = 1.0f / det;
        const Vec3<float> s = of - p0;
        const float u = dot(s, p) * inv;
        const Vec3<float> q = cross(s, e1);
        const float v = dot(df, q) * inv;
        const float tt = dot(e2, q) * inv;
        if (u > 0 && v > 0 && u + v < 1 && tt > 0 && tt < best) best = tt, bt = std::int64_t(k);
      }
      t[i] = bt < 0 ? kInf : double(best);
      tri[i] = bt;
    }
  };
}

/// The certified MeshCaster: exact class, t within 1 ulp.
struct CertifiedCaster {
  MeshCaster<cast::Certified> c;
  explicit CertifiedCaster(const OwnedMesh& m)
      : c(VertexArray(&m.v[0].x, m.v.size()), IndexArray{m.f[0].data(), m.f.size()}) {}
  void operator()(std::span<const Vec3<double>> o, std::span<const Vec3<double>> d, std::span<double> t,
                  std::span<std::int64_t> tri) const {
    for (std::size_t i = 0; i < o.size(); ++i) {
      const MeshHit h = c.closest({o[i], d[i]});
      t[i] = h.hit() ? h.t : kInf;
      tri[i] = h.hit() ? std::int64_t(h.triangle) : -1;
    }
  }
};

/// The counts check_caster must report, tallied by brute force over every triangle.
CasterTally brute_tally(const OwnedMesh& m, const verify::CasterRays& rays, std::span<const CasterAnswer> answers,
                        bool f32) {
  CasterTally c;
  auto note = [&](const char* kind, std::size_t ray) { c.reproducers.push_back({kind, ray, ""}); };
  for (std::size_t i = 0; i < rays.rays.size(); ++i) {
    const Ray<double>& r = rays.rays[i];
    const CasterAnswer& a = answers[i];
    ++c.rays;
    if (!r.valid()) {
      ++c.invalid_rays;
      if (a.failed) ++c.invalid_failures, note("invalid-ray-failure", i);
      else if (a.triangle != -1) ++c.invalid_hit, note("invalid-ray-hit", i);
      continue;
    }
    if (a.failed) {
      ++c.caster_failures, note("caster-failure", i);
      continue;
    }
    const Brute e = brute_closest(m, r);
    if (e.tri >= 0) ++c.hits;
    const bool c_hit = a.triangle >= 0;
    if (std::isnan(a.t) || a.triangle < -1 || a.triangle >= std::int64_t(m.f.size()) || (!c_hit && a.t != kInf) ||
        (c_hit && !(a.t >= 0 && a.t < kInf))) {
      ++c.garbage, note("garbage", i);
      continue;
    }
    if (e.tri < 0 && !c_hit) continue;
    if (!c_hit) {
      if (e.coplanar) ++c.coplanar_miss;
      else ++c.false_miss, note("false-miss", i);
      continue;
    }
    const TriangleHit<double> hc = exact::intersect(r, tri_of(m, std::size_t(a.triangle)));
    if (origin_contact(hc) && a.t == 0) continue;
    if (e.tri < 0) {
      ++c.false_hit, note("false-hit", i);
      continue;
    }
    double tc;
    bool cop;
    if (!crossing(hc, tc, cop) || tc != e.t) {
      ++c.wrong_triangle, note("wrong-triangle", i);
      if (crossing(hc, tc, cop) && (f32 ? ulp_distance(float(tc), float(e.t)) : ulp_distance(tc, e.t)) <= 1)
        ++c.wrong_triangle_near;
      continue;
    }
    if (cop || e.coplanar) continue;
    const std::uint64_t d = f32 ? ulp_distance(float(a.t), float(e.t)) : ulp_distance(a.t, e.t);
    c.max_ulps = std::max(c.max_ulps, d);
    if (d > 1) ++c.t_over_1ulp, note("t-error", i);
  }
  return c;
}

void expect_same_counts(const CasterTally& got, const CasterTally& want) {
  for (const verify::CasterCounter& counter : verify::kCasterCounters)
    EXPECT_EQ(count_of(got, counter), count_of(want, counter)) << counter.key;
  // Ray by ray, when every finding kept its reproducer.
  if (got.reproducers.size() != got.findings()) return;
  std::vector<std::pair<std::string, std::size_t>> g, w;
  for (const auto& r : got.reproducers) g.emplace_back(r.kind, r.ray);
  for (const auto& r : want.reproducers) w.emplace_back(r.kind, r.ray);
  std::sort(g.begin(), g.end());
  std::sort(w.begin(), w.end());
  EXPECT_EQ(g, w);
  for (const auto& r : got.reproducers)
    if (std::find(w.begin(), w.end(), std::make_pair(r.kind, r.ray)) == w.end()) ADD_FAILURE() << "not in the tally: " << r.line;
}

verify::CasterCheckOptions small_options() {
  verify::CasterCheckOptions o;
  o.random_rays = 400;
  o.max_rays_per_set = 1500;
  return o;
}

TEST(CasterCheck, ExactBruteForceCasterHasNoFinding) {
  for (const OwnedMesh& m : {cube(), star(3), hull(5)}) {
    const CasterTally c = verify::check_caster(exact_brute_caster(m), m.view(), small_options());
    EXPECT_EQ(c.findings(), 0u) << m.name << "\n" << verify::summary_text(c);
    EXPECT_EQ(c.max_ulps, 0u) << m.name;
    EXPECT_GT(c.hits, c.rays / 4) << m.name;  // the ray sets do cross the mesh
    EXPECT_EQ(c.coplanar_miss, 0u);
  }
}

TEST(CasterCheck, ExactCasterPassesTheGtestMacro) {
  const OwnedMesh m = cube();
  EXPECT_CASTER_MATCHES_EXACT(exact_brute_caster(m), m.view());
}

// The certified MeshCaster orders crossings by t within 1 ulp: where two triangles are crossed
// within an ulp or two of each other it may name the later one. Nothing else is found.
TEST(CasterCheck, CertifiedCasterOnlyMisordersNearTies) {
  for (const OwnedMesh& m : {cube(), star(4)}) {
    const CertifiedCaster caster(m);
    verify::CasterCheckOptions o = small_options();
    o.reproducers = 1000000;
    const CasterTally c = verify::check_caster(std::cref(caster), m.view(), o);
    EXPECT_EQ(c.findings(), c.wrong_triangle) << verify::summary_text(c);
    EXPECT_LE(c.max_ulps, 1u);
    const verify::CasterRays rays = verify::caster_rays(m.view(), o);
    for (const auto& r : c.reproducers) {
      const Ray<double>& ray = rays.rays[r.ray];
      const Brute first = brute_closest(m, ray);
      MeshHit h = caster.c.closest(ray);
      const TriangleHit<double> got = exact::intersect(ray, tri_of(m, h.triangle));
      EXPECT_LE(ulp_distance(got.t, first.t), 2u) << r.line;
      EXPECT_NE(h.triangle, std::uint32_t(first.tri)) << r.line;
    }
  }
}

TEST(CasterCheck, StrictBarycentricFloatCasterIsCaughtWithReproducers) {
  const OwnedMesh m = star(7);
  verify::CasterCheckOptions o = small_options();
  o.precision = verify::CasterPrecision::float32;
  const CasterTally c = verify::check_caster(strict_float_caster(m), m.view(), o);
  EXPECT_GT(c.false_miss, 0u) << verify::summary_text(c);
  EXPECT_GT(c.findings(), 0u);
  bool leak_repro = false;
  for (const auto& r : c.reproducers) {
    if (r.kind != "false-miss") continue;
    EXPECT_NE(r.line.find("mesh=star"), std::string::npos) << r.line;
    EXPECT_NE(r.line.find("caster: tri -1 t inf"), std::string::npos) << r.line;
    leak_repro |= r.line.find("set=leak") != std::string::npos;
  }
  EXPECT_TRUE(leak_repro) << verify::summary_text(c);
  // Its leak rays leak: the set's findings are counted per set.
  for (const auto& s : c.sets)
    if (s.set == "leak") {
      EXPECT_GT(s.findings, 0u);
      EXPECT_GT(s.false_miss, 0u);
    }
  const auto fail = ::rayproof::gtest::caster_matches_exact(strict_float_caster(m), m.view(), o);
  EXPECT_FALSE(fail);
  EXPECT_NE(std::string(fail.message()).find("false-miss set="), std::string::npos);
}

TEST(CasterCheck, GarbageAndThrowingCasterIsReportedAndTheRunGoesOn) {
  const OwnedMesh m = cube();
  const CertifiedCaster good(m);
  auto bad = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d, std::span<double> t,
                 std::span<std::int64_t> tri) {
    if (!(Ray<double>{o[0], d[0]}.valid())) throw std::runtime_error("cannot cast an invalid ray");
    good(o, d, t, tri);
    if (std::abs(o[0].x - 0.5) < 0.1) t[0] = std::nan("");   // garbage: NaN t
    else if (o[0].y > 1.5) tri[0] = 1000;                     // garbage: triangle out of range
  };
  verify::CasterCheckOptions o = small_options();
  o.batch = 1;
  const CasterTally c = verify::check_caster(bad, m.view(), o);
  EXPECT_EQ(c.invalid_failures, c.invalid_rays);
  EXPECT_GT(c.invalid_rays, 0u);
  EXPECT_GT(c.garbage, 0u);
  EXPECT_EQ(c.caster_failures, 0u);  // only the invalid rays threw
  std::size_t set_total = 0;
  for (const auto& s : c.sets) set_total += s.rays;
  EXPECT_EQ(set_total, c.rays);
  bool noted = false;
  for (const auto& n : c.notes) noted |= n.find("cannot cast an invalid ray") != std::string::npos;
  EXPECT_TRUE(noted);
  // The same rays with the answers of a caster that hits on every invalid ray.
  const verify::CasterRays rays = verify::caster_rays(m.view(), o);
  std::vector<CasterAnswer> answers(rays.rays.size(), CasterAnswer{0.5, 0});
  const CasterTally h = verify::CasterJudge(m.view()).judge(rays, answers, o);
  EXPECT_EQ(h.invalid_hit, h.invalid_rays);
}

TEST(CasterCheck, CountsEqualABruteForceExactTally) {
  struct Case {
    OwnedMesh m;
    bool f32;
  };
  for (const Case& k : {Case{cube(), true}, Case{star(11), true}, Case{hull(13), true}, Case{star(17), false}}) {
    const OwnedMesh& m = k.m;
    verify::CasterCheckOptions o = small_options();
    o.max_rays_per_set = 600;
    o.reproducers = 1000000;
    o.precision = k.f32 ? verify::CasterPrecision::float32 : verify::CasterPrecision::float64;
    const verify::CasterRays rays = verify::caster_rays(m.view(), o);
    std::vector<CasterAnswer> answers(rays.rays.size());
    std::string error;
    // The float caster, with a t off by a few ulps, a wrong triangle and a garbage answer mixed in.
    verify::run_caster(strict_float_caster(m), {}, rays.rays, 256, answers, error);
    for (std::size_t i = 0; i < answers.size(); i += 7) {
      if (answers[i].triangle < 0) continue;
      if (i % 3 == 0) answers[i].t = std::nextafter(std::nextafter(answers[i].t, kInf), kInf) * (1 + 1e-7);
      else if (i % 3 == 1) answers[i].triangle = (answers[i].triangle + 1) % std::int64_t(m.f.size());
      else answers[i].t = -1;
    }
    const CasterTally got = verify::CasterJudge(m.view()).judge(rays, answers, o);
    const CasterTally want = brute_tally(m, rays, answers, k.f32);
    SCOPED_TRACE(m.name);
    expect_same_counts(got, want);
    EXPECT_GT(got.false_miss + got.wrong_triangle + got.t_over_1ulp, 0u);
    std::size_t kept = got.reproducers.size();
    EXPECT_EQ(kept, got.findings());  // one reproducer per finding when the cap is high
    // And the exact answers themselves: nothing found, by both.
    verify::run_caster(exact_brute_caster(m), {}, rays.rays, 256, answers, error);
    const CasterTally none = verify::CasterJudge(m.view()).judge(rays, answers, o);
    expect_same_counts(none, brute_tally(m, rays, answers, k.f32));
    EXPECT_EQ(none.findings(), 0u);
  }
}

TEST(CasterCheck, AnyHitAnswersAreJudged) {
  const OwnedMesh m = star(19);
  const CertifiedCaster good(m);
  auto any_right = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d, std::span<std::uint8_t> out) {
    for (std::size_t i = 0; i < o.size(); ++i) out[i] = good.c.any({o[i], d[i]}, {std::numeric_limits<double>::denorm_min(), kInf});
  };
  auto any_never = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>>, std::span<std::uint8_t> out) {
    for (std::size_t i = 0; i < o.size(); ++i) out[i] = 0;
  };
  const verify::CasterCheckOptions o = small_options();
  const CasterTally right = verify::check_caster(std::cref(good), m.view(), o, any_right);
  EXPECT_EQ(right.any_false_miss + right.any_false_hit, 0u) << verify::summary_text(right);
  EXPECT_EQ(right.any_rays, right.rays - right.invalid_rays);
  const CasterTally never = verify::check_caster(std::cref(good), m.view(), o, any_never);
  EXPECT_EQ(never.any_false_miss + never.any_coplanar_miss, never.hits);
  EXPECT_GT(never.any_false_miss, 0u);
}

// The summary text is made from kCasterCounters: one `key value` line per counter (labels where
// given), the occlusion counts only when occlusion was asked, `findings` last.
TEST(CasterTally, SummaryTextHasOneLinePerCounter) {
  CasterTally tally;
  std::uint64_t next = 1;
  for (const verify::CasterCounter& counter : verify::kCasterCounters)
    if (counter.member) tally.*counter.member = next++;
  tally.any_rays = 0;
  tally.sets.push_back({"leak", 7, 3, 2});
  tally.notes.push_back("a note");
  tally.reproducers.push_back({"false-miss", 4, "false-miss set=leak ..."});
  const std::uint64_t findings = tally.false_miss + tally.false_hit + tally.wrong_triangle + tally.t_over_1ulp +
                                 tally.garbage + tally.caster_failures + tally.any_false_miss + tally.any_false_hit +
                                 tally.invalid_hit + tally.invalid_failures;
  EXPECT_EQ(tally.findings(), findings);
  EXPECT_EQ(verify::summary_text(tally),
            "rays               1\n"
            "hits               2\n"
            "false_miss         3\n"
            "coplanar_miss      4\n"
            "false_hit          5\n"
            "wrong_triangle     6\n"
            "  within_1ulp      7\n"
            "t_over_1ulp        8\n"
            "max_ulps           9\n"
            "garbage            10\n"
            "caster_failures    11\n"
            "invalid_rays       16\n"
            "invalid_hit        17\n"
            "invalid_failures   18\n"
            "findings           " + std::to_string(findings) + "\n"
            "set leak       rays       7  findings       3  false_miss 2\n"
            "note: a note\n"
            "false-miss set=leak ...\n");
  tally.any_rays = 12;
  const std::string with_occlusion = verify::summary_text(tally);
  EXPECT_NE(with_occlusion.find("caster_failures    11\n"
                                "any_rays           12\n"
                                "any_false_miss     13\n"
                                "any_false_hit      14\n"
                                "any_coplanar_miss  15\n"
                                "invalid_rays       16\n"),
            std::string::npos)
      << with_occlusion;
}

// docs/check.md explains every count by its key, and lists the findings `findings` adds up.
TEST(CasterTally, EveryCounterIsInTheDocs) {
  std::ifstream in(std::string(RAYPROOF_DATA_DIR) + "/../docs/check.md");
  ASSERT_TRUE(in) << "docs/check.md";
  const std::string docs((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto sum_at = docs.find("`findings` adds up the findings:");
  ASSERT_NE(sum_at, std::string::npos);
  const std::string sum = docs.substr(sum_at, docs.find(';', sum_at) - sum_at);
  for (const verify::CasterCounter& counter : verify::kCasterCounters) {
    const std::string key = "`" + std::string(counter.key) + "`";
    EXPECT_NE(docs.find(key), std::string::npos) << key;
    EXPECT_FALSE(counter.meaning.empty()) << key;
    if (counter.member) EXPECT_EQ(sum.find(key) != std::string::npos, counter.finding) << key << " in: " << sum;
  }
}

// A judgement's tally merges its chunks counter by counter: on more rays than one chunk holds,
// the counts equal the sums over the rays judged one set at a time (max_ulps: the largest).
TEST(CasterTally, ChunksAndSetsAddUp) {
  const OwnedMesh m = star(23);
  verify::CasterCheckOptions o = small_options();
  o.precision = verify::CasterPrecision::float32;
  const verify::CasterRays rays = verify::caster_rays(m.view(), o);
  ASSERT_GT(rays.rays.size(), 1024u);  // judged in several chunks (of 512 rays)
  std::vector<CasterAnswer> answers(rays.rays.size());
  std::string error;
  verify::run_caster(strict_float_caster(m), {}, rays.rays, 256, answers, error);
  const verify::CasterJudge judge(m.view());
  const CasterTally whole = judge.judge(rays, answers, o);
  verify::CasterCounts sum;
  for (std::size_t set = 0; set < rays.names.size(); ++set) {
    verify::CasterRays one;
    one.names = rays.names;
    std::vector<CasterAnswer> one_answers;
    for (std::size_t i = 0; i < rays.rays.size(); ++i)
      if (rays.set[i] == set) {
        one.rays.push_back(rays.rays[i]);
        one.set.push_back(rays.set[i]);
        one_answers.push_back(answers[i]);
      }
    const CasterTally part = judge.judge(one, one_answers, o);
    EXPECT_EQ(part.sets[set].rays, whole.sets[set].rays) << rays.names[set];
    EXPECT_EQ(part.sets[set].findings, whole.sets[set].findings) << rays.names[set];
    for (const verify::CasterCounter& counter : verify::kCasterCounters) {
      if (!counter.member) continue;
      std::uint64_t& total = sum.*counter.member;
      total = counter.maximum ? std::max(total, part.*counter.member) : total + part.*counter.member;
    }
  }
  for (const verify::CasterCounter& counter : verify::kCasterCounters)
    EXPECT_EQ(count_of(whole, counter), count_of(sum, counter)) << counter.key;
  EXPECT_GT(whole.false_miss, 0u);
}

// CasterCheck, the tally's name before CasterTally, still names the same type for a release.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
TEST(CasterTally, TheOldNameCasterCheckStillCompiles) {
  static_assert(std::is_same_v<verify::CasterCheck, verify::CasterTally>);
  const OwnedMesh m = cube();
  const verify::CasterCheck old = verify::check_caster(exact_brute_caster(m), m.view(), small_options());
  EXPECT_GT(old.rays, 0u);
  EXPECT_EQ(old.findings(), 0u) << verify::summary_text(old);
}
#pragma GCC diagnostic pop

TEST(CasterCheck, BadInputIsRefused) {
  const OwnedMesh m = cube();
  verify::CasterCheckOptions o;
  o.sets = {"nope"};
  EXPECT_THROW((void)verify::caster_rays(m.view(), o), std::invalid_argument);
  const verify::CasterRays rays = verify::caster_rays(m.view(), small_options());
  std::vector<CasterAnswer> few(rays.rays.size() - 1);
  EXPECT_THROW((void)verify::CasterJudge(m.view()).judge(rays, few), std::invalid_argument);
  OwnedMesh broken = cube();
  broken.f[0][1] = 99;
  EXPECT_THROW((void)verify::CasterJudge(broken.view()), MeshInputError);
}

}  // namespace
}  // namespace rayproof
