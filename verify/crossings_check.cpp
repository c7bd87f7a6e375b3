// The judgement of someone else's all-hits function on a mesh (rayproof/verify/crossings_check.h):
// ExactMesh::ray_crossings lists each ray's exact contacts (crossings once, touches apart); each
// hit is matched to the contact its triangle meets the ray at (the certified class of that
// triangle; where contacts lie within two ulps, an exact comparison of t in GMP rationals), and
// the contacts count what they got against what they want.
#include "rayproof/verify/crossings_check.h"

#include <fmt/core.h>
#include <gmpxx.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <tuple>

#include "rayproof/certified/intersect.h"
#include "rayproof/float_util.h"
#include "rayproof/scene/contains.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/verify/exact.h"
#include "verify/judge_frame.h"
#include "verify/rounded_t.h"

namespace rayproof::verify {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
const TRange kPositive{std::numeric_limits<double>::denorm_min(), kInf};  // contacts at t > 0

std::string num(double x) { return exact_number(x); }

double two_ulps_up(double x) { return next_up(next_up(x)); }
double two_ulps_down(double x) { return next_down(next_down(x)); }

struct QVec {
  mpq_class x, y, z;
};
QVec q(const Vec3<double>& v) { return {v.x, v.y, v.z}; }
QVec sub(const QVec& a, const QVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
mpq_class qdot(const QVec& a, const QVec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
QVec qcross(const QVec& a, const QVec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// The exact t = ((p0 - o) . n) / (d . n) of a ray meeting a triangle that is not parallel to it.
mpq_class exact_t(const Ray<double>& r, const Triangle<double>& tri) {
  const QVec p0 = q(tri.p0), n = qcross(sub(q(tri.p1), p0), sub(q(tri.p2), p0));
  return mpq_class(qdot(sub(p0, q(r.o)), n) / qdot(q(r.d), n));
}
/// Whether that exact t is 0 (the origin on the triangle's plane).
bool exact_t_zero(const Ray<double>& r, const Triangle<double>& tri) {
  const QVec p0 = q(tri.p0), n = qcross(sub(q(tri.p1), p0), sub(q(tri.p2), p0));
  return sgn(qdot(sub(p0, q(r.o)), n)) == 0;
}

/// One exact contact point of a ray: a crossing point (`want` crossings there) or a touch.
struct Point {
  double t = 0;           ///< the listed t (within one ulp of the exact t)
  std::uint32_t triangle = 0;  ///< the reference's triangle there
  std::uint32_t want = 0;      ///< crossings at this point (0: a touch)
  std::uint32_t got = 0;       ///< hits matched to it
  double rounded = kNaN<double>;  ///< the exact t correctly rounded, once needed
};

/// The mesh as given: its triangles by number.
struct MeshTriangles {
  std::string name;
  std::vector<Vec3<double>> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  [[nodiscard]] Triangle<double> triangle(std::size_t k) const {
    const auto& f = triangles[k];
    return {vertices[f[0]], vertices[f[1]], vertices[f[2]]};
  }
};

}  // namespace

struct CrossingsJudge::State : MeshTriangles {
  ExactMesh mesh;
  explicit State(const CasterMesh& m)
      : MeshTriangles{m.name, {m.vertices.begin(), m.vertices.end()}, {m.triangles.begin(), m.triangles.end()}},
        mesh(VertexArray(reinterpret_cast<const double*>(m.vertices.data()), m.vertices.size()),
             IndexArray{m.triangles.empty() ? nullptr : m.triangles.data()->data(), m.triangles.size()}) {}
};

namespace {

/// The judgement of one ray: its counts (the ray's share of the tally).
struct RayJudgement {
  const MeshTriangles& s;
  const CrossingsCheckOptions& opt;
  bool float32;
  std::vector<Point> points;
  std::vector<std::uint32_t> coplanar;  ///< triangles holding the ray, hit already

  [[nodiscard]] std::uint64_t ulps(double a, double b) const {
    return float32 ? ulp_distance(static_cast<float>(a), static_cast<float>(b)) : ulp_distance(a, b);
  }

  double rounded_t(const Ray<double>& ray, Point& p) const {
    if (std::isnan(p.rounded)) {
      const Triangle<double> tri = s.triangle(p.triangle);
      const std::optional<double> r = round_t(ray, tri, p.t);
      p.rounded = r ? *r : exact::intersect(ray, tri).t;
    }
    return p.rounded;
  }

  /// The point of `points` the triangle meets the ray at (its certified t `t`), or null.
  Point* match(const Ray<double>& ray, std::uint32_t triangle, double t) {
    const double lo = two_ulps_down(t), hi = two_ulps_up(t);
    auto first = std::lower_bound(points.begin(), points.end(), lo, [](const Point& p, double x) { return p.t < x; });
    auto last = first;
    while (last != points.end() && last->t <= hi) ++last;
    if (first == last) return nullptr;
    if (last - first == 1) return &*first;  // one contact near: the triangle's (it meets the ray there)
    for (auto it = first; it != last; ++it)
      if (it->triangle == triangle) return &*it;  // a triangle meets the ray at one point
    const mpq_class mine = exact_t(ray, s.triangle(triangle));
    for (auto it = first; it != last; ++it)
      if (exact_t(ray, s.triangle(it->triangle)) == mine) return &*it;
    return nullptr;
  }

  CrossingsCounts judge(const Ray<double>& ray, const RayCrossings& ref, const CrossingsAnswer& a) {
    CrossingsCounts c;
    c.rays = 1;
    if (!ray.valid()) {
      c.invalid_rays = 1;
      if (a.failed) c.invalid_failures = 1;
      else if (!a.hits.empty()) c.invalid_hit = 1;
      return c;
    }
    c.crossings = ref.crossings.size();
    if (a.failed) {
      c.failures = 1;
      return c;
    }
    c.hits = a.hits.size();
    for (std::size_t k = 1; k < a.hits.size(); ++k)
      if (a.hits[k].t < a.hits[k - 1].t) c.wrong_order = 1;
    // The contact points in t order: crossings (k at one point: equal t and triangle) and point touches.
    points.clear();
    coplanar.clear();
    for (const Crossing& x : ref.crossings) {
      if (!points.empty() && points.back().want > 0 && points.back().t == x.t && points.back().triangle == x.triangle)
        ++points.back().want;
      else
        points.push_back({x.t, x.triangle, 1});
    }
    for (const Touch& x : ref.touches)
      if (x.contact != Contact::coplanar) points.push_back({x.t, x.triangle, 0});
    std::stable_sort(points.begin(), points.end(), [](const Point& p, const Point& r) { return p.t < r.t; });
    const std::size_t n_triangles = s.triangles.size();
    for (const CrossingHit& h : a.hits) {
      if (!std::isfinite(h.t) || h.triangle < 0 || static_cast<std::uint64_t>(h.triangle) >= n_triangles) {
        ++c.garbage;
        continue;
      }
      const auto k = static_cast<std::uint32_t>(h.triangle);
      const Triangle<double> tri = s.triangle(k);
      const TriangleHit<double> th = certified::intersect(ray, tri);
      if (th.contact == Contact::coplanar) {
        if (std::isnan(th.t2)) {
          ++c.no_contact;
        } else if (th.t2 == 0) {
          ++c.at_origin;  // the triangle holds the ray at t = 0 only
        } else if (std::find(coplanar.begin(), coplanar.end(), k) != coplanar.end()) {
          ++c.duplicates;
        } else {
          coplanar.push_back(k);
          ++c.touch_hits;
        }
        continue;
      }
      if (th.contact != Contact::interior && th.contact != Contact::edge && th.contact != Contact::vertex) {
        ++c.no_contact;
        continue;
      }
      if (th.t <= std::numeric_limits<double>::denorm_min() && exact_t_zero(ray, tri)) {
        ++c.at_origin;
        continue;
      }
      Point* p = match(ray, k, th.t);
      if (!p) {
        ++c.no_contact;
        continue;
      }
      ++p->got;
      if (p->want == 0) continue;
      const std::uint64_t u = ulps(h.t, rounded_t(ray, *p));
      c.max_ulps = std::max(c.max_ulps, u);
      if (u > opt.max_ulps) ++c.t_over_tolerance;
    }
    for (const Point& p : points) {
      if (p.want == 0) {
        if (p.got > 0) ++c.touch_hits, c.duplicates += p.got - 1;
      } else if (p.got < p.want) {
        c.missing += p.want - p.got;
      } else {
        c.duplicates += p.got - p.want;
      }
    }
    return c;
  }
};

std::string hits_text(const std::vector<CrossingHit>& hits) {
  std::string out = fmt::format("{} hit{}", hits.size(), hits.size() == 1 ? "" : "s");
  for (std::size_t k = 0; k < hits.size() && k < 12; ++k)
    out += fmt::format(" {}@{}", num(hits[k].t), hits[k].triangle);
  if (hits.size() > 12) out += " ...";
  return out;
}

std::string exact_text(const RayCrossings& ref) {
  std::string out = fmt::format("{} crossing{}", ref.crossings.size(), ref.crossings.size() == 1 ? "" : "s");
  for (std::size_t k = 0; k < ref.crossings.size() && k < 12; ++k)
    out += fmt::format(" {}@{}:{}", num(ref.crossings[k].t), ref.crossings[k].triangle, to_string(ref.crossings[k].direction));
  if (ref.crossings.size() > 12) out += " ...";
  out += fmt::format(", {} touch{}", ref.touches.size(), ref.touches.size() == 1 ? "" : "es");
  for (std::size_t k = 0; k < ref.touches.size() && k < 6; ++k)
    out += fmt::format(" {}@{}:{}", num(ref.touches[k].t), ref.touches[k].triangle, to_string(ref.touches[k].contact));
  if (ref.touches.size() > 6) out += " ...";
  return out;
}

/// "t_over_tolerance" -> "t-over-tolerance": the reproducers' kinds.
std::string kind_of(std::string_view key) {
  std::string k(key);
  std::replace(k.begin(), k.end(), '_', '-');
  return k;
}

}  // namespace

CrossingsJudge::CrossingsJudge(const CasterMesh& mesh) : state_(std::make_unique<State>(mesh)) {}
CrossingsJudge::~CrossingsJudge() = default;
CrossingsJudge::CrossingsJudge(CrossingsJudge&&) noexcept = default;
CrossingsJudge& CrossingsJudge::operator=(CrossingsJudge&&) noexcept = default;

CrossingsTally CrossingsJudge::judge(const CasterRays& rays, std::span<const CrossingsAnswer> answers,
                                     const CrossingsCheckOptions& opt) const {
  const std::size_t n = rays.rays.size();
  if (answers.size() != n || rays.set.size() != n)
    throw std::invalid_argument(fmt::format("judge: {} answers for {} rays", answers.size(), n));
  const State& s = *state_;
  const bool float32 = opt.precision == CasterPrecision::float32;
  CrossingsTally tally;
  tally.precision = opt.precision;
  tally.tolerance_ulps = opt.max_ulps;
  tally.notes = rays.notes;
  std::vector<RayCrossings> ref(n), baseline(n);
  std::vector<CrossingsCounts> verdicts(n);
  KindQuota quota(opt.reproducers);
  for (const auto& name : rays.names) tally.sets.push_back({name, 0, 0, 0, 0});
  {  // Warm-up, untimed.
    const std::size_t m = std::min<std::size_t>(n, 64);
    s.mesh.ray_crossings(std::span(rays.rays).first(m), std::span(baseline).first(m), kPositive, 1);
  }
  auto in_arena = [&](auto&& f) {
    if (opt.threads > 0) tbb::task_arena(opt.threads).execute(f);
    else f();
  };
  const auto rays_of = [&](std::size_t b, std::size_t e) { return std::span(rays.rays).subspan(b, e - b); };
  std::tie(tally.judge_seconds, tally.crossings_seconds) = time_by_set(
      rays.set, tally.sets,
      [&](std::size_t b, std::size_t e) {
        s.mesh.ray_crossings(rays_of(b, e), std::span(ref).subspan(b, e - b), kPositive, opt.threads);
        in_arena([&] {
          tbb::parallel_for(tbb::blocked_range<std::size_t>(b, e, 64), [&](const tbb::blocked_range<std::size_t>& r) {
            RayJudgement j{s, opt, float32, {}, {}};
            for (std::size_t i = r.begin(); i < r.end(); ++i) verdicts[i] = j.judge(rays.rays[i], ref[i], answers[i]);
          });
        });
        for (std::size_t i = b; i < e; ++i) {
          const CrossingsCounts& v = verdicts[i];
          add_counts(tally, v, kCrossingsCounters);
          ContainsSetCounts& set = tally.sets[rays.set[i]];
          ++set.points;
          set.findings += v.findings();
          tally.rays_with_findings += v.findings() > 0;
          for (const CrossingsCounter& counter : kCrossingsCounters) {
            if (!counter.finding || v.*counter.member == 0) continue;
            const std::string kind = kind_of(counter.key);
            if (!quota.keep(kind)) continue;
            const Ray<double>& r = rays.rays[i];
            const std::string extra =
                counter.member == &CrossingsCounts::t_over_tolerance
                    ? fmt::format(" ({} ulps of {})", v.max_ulps, float32 ? "float" : "double")
                    : std::string();
            tally.reproducers.push_back(
                {kind, i,
                 fmt::format("{} set={} mesh={} ray {} {} exact: {} answer: {}{}", kind, rays.names[rays.set[i]], s.name,
                             exact_point(r.o), exact_point(r.d), r.valid() ? exact_text(ref[i]) : std::string("invalid"),
                             answers[i].failed ? std::string("failed") : hits_text(answers[i].hits), extra)});
          }
        }
      },
      [&](std::size_t b, std::size_t e) {
        s.mesh.ray_crossings(rays_of(b, e), std::span(baseline).subspan(b, e - b), kPositive, opt.threads);
      });
  return tally;
}

CasterRays crossings_rays(const CasterMesh& mesh, const CrossingsCheckOptions& opt) {
  CasterCheckOptions c;
  c.precision = opt.precision;
  c.random_rays = opt.random_rays;
  c.max_rays_per_set = opt.max_rays_per_set;
  c.seed = opt.seed;
  c.sets = opt.sets;
  return caster_rays(mesh, c);
}

void run_crossings(const CrossingsFunction& fn, std::span<const Ray<double>> rays, std::size_t batch,
                   std::span<CrossingsAnswer> out, std::string& error) {
  if (out.size() != rays.size()) throw std::invalid_argument("run_crossings: output size differs from ray count");
  std::vector<Vec3<double>> o, d;
  std::vector<std::vector<CrossingHit>> hits;
  run_in_batches(
      rays.size(), batch, error,
      [&](std::size_t at, std::size_t n) {
        o.resize(n), d.resize(n);
        for (std::size_t k = 0; k < n; ++k) o[k] = rays[at + k].o, d[k] = rays[at + k].d;
        hits.assign(n, {});
        fn(o, d, hits);
      },
      [&](std::size_t at, std::size_t n, bool failed) {
        for (std::size_t k = 0; k < n; ++k) {
          out[at + k].failed = failed;
          out[at + k].hits = failed || k >= hits.size() ? std::vector<CrossingHit>{} : std::move(hits[k]);
        }
      });
}

namespace {

CrossingsTally run_and_judge(const CrossingsFunction& fn, const CasterMesh& mesh, const CasterRays& rays,
                             const CrossingsCheckOptions& opt) {
  const CrossingsJudge judge(mesh);
  std::vector<CrossingsAnswer> answers(rays.rays.size());
  std::string error;
  run_crossings(fn, rays.rays, opt.batch, answers, error);
  CrossingsTally tally = judge.judge(rays, answers, opt);
  if (!error.empty()) tally.notes.push_back("the function threw: " + error);
  return tally;
}

}  // namespace

CrossingsTally check_crossings(const CrossingsFunction& fn, const CasterMesh& mesh, const CrossingsCheckOptions& opt) {
  return run_and_judge(fn, mesh, crossings_rays(mesh, opt), opt);
}

CrossingsTally check_crossings(const CrossingsFunction& fn, const CasterMesh& mesh, std::span<const Ray<double>> user_rays,
                               const CrossingsCheckOptions& opt) {
  CasterRays rays;
  rays.rays.assign(user_rays.begin(), user_rays.end());
  if (opt.precision == CasterPrecision::float32)
    for (Ray<double>& r : rays.rays) r = {r.o.cast<float>().cast<double>(), r.d.cast<float>().cast<double>()};
  rays.set.assign(rays.rays.size(), 0);
  rays.names = {"user"};
  return run_and_judge(fn, mesh, rays, opt);
}

std::string summary_text(const CrossingsTally& tally) {
  return fmt::format("{:<18} {}, t within {} ulp{}\n", "precision",
                     tally.precision == CasterPrecision::float32 ? "float32" : "float64", tally.tolerance_ulps,
                     tally.tolerance_ulps == 1 ? "" : "s") +
         counters_text(kCrossingsCounters, tally, 18, [](const auto&) { return true; }) +
         cost_text(tally.sets, "rays", "ray_crossings", tally.judge_seconds, tally.crossings_seconds) +
         notes_text(tally.notes, tally.reproducers);
}

}  // namespace rayproof::verify
