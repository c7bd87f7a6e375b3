// The judgement of a whole caster on a mesh (rayproof/verify/caster_check.h): the certified
// MeshCaster gives each ray's first crossing; exact per-triangle tests settle the caster's triangle,
// ties and the correctly rounded t. Only the disagreements and the t errors cost exact arithmetic.
// The ray sets are made in caster_rays.cpp.
#include "rayproof/verify/caster_check.h"

#include <fmt/core.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <tuple>

#include "rayproof/certified/intersect.h"
#include "rayproof/certified_expansion.h"
#include "rayproof/certified_filter.h"
#include "rayproof/float_util.h"
#include "rayproof/scene/contains.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/verify/exact.h"

namespace rayproof::verify {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
const TRange kPositive{std::numeric_limits<double>::denorm_min(), kInf};  // crossings at t > 0

std::string num(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return fmt::format("{}", x);  // shortest round-trip
}

std::string ray_text(const Ray<double>& r) {
  return fmt::format("{} {} {} {} {} {}", num(r.o.x), num(r.o.y), num(r.o.z), num(r.d.x), num(r.d.y), num(r.d.z));
}

/// What an exact triangle result means for a caster judged at t > 0.
struct Contact1 {
  enum Kind : std::uint8_t { none, origin, point, coplanar } kind = none;
  double t = kInf;  ///< t of the contact (a coplanar range: its start)
};

Contact1 contact_of(const TriangleHit<double>& h) {
  switch (h.contact) {
    case Contact::interior: case Contact::edge: case Contact::vertex:
      if (h.t > 0) return {Contact1::point, h.t};
      if (h.t == 0) return {Contact1::origin, 0};
      return {};
    case Contact::coplanar:
      if (std::isnan(h.t)) return {};
      if (h.t > 0) return {Contact1::coplanar, h.t};
      if (h.t == 0) return {Contact1::origin, 0};  // the origin lies in the triangle
      return {};
    default: return {};
  }
}

/// The correctly rounded t of a ray crossing a triangle's plane (d . n != 0), given t0 within one
/// ulp of it: the exact signs of N - m D at the midpoints m around t0 (N = (p0 - o) . n, D = d . n,
/// floating-point expansions). Nothing when the inputs are outside the range where every product is
/// exact (the caller then asks exact::intersect).
std::optional<double> round_t(const Ray<double>& r, const Triangle<double>& tri, double t0) {
  using certified::Bounded;
  using certified::Expansion;
  const double at = std::fabs(t0);
  if (!(at > 0x1p-200 && at < 0x1p200)) return std::nullopt;
  if (!certified::in_range<-150, 150>(r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, tri.p0.x, tri.p0.y, tri.p0.z,
                                      tri.p1.x, tri.p1.y, tri.p1.z, tri.p2.x, tri.p2.y, tri.p2.z))
    return std::nullopt;
  // First in Wide with running error bounds (certified_filter.h); the expansions only where that
  // cannot tell the sign.
  const Vec3<Bounded> p0 = certified::lift(tri.p0);
  const Vec3<Bounded> nb = cross(certified::lift(tri.p1) - p0, certified::lift(tri.p2) - p0);
  const Bounded Nb = dot(p0 - certified::lift(r.o), nb), Db = dot(certified::lift(r.d), nb);
  std::optional<int> sdb = certified::kFilterAvailable ? certified::sign(Db) : std::nullopt;
  std::optional<Expansion> N, D;
  auto exact_parts = [&] {
    if (N) return;
    const certified::ExpVec3 e1 = certified::diff3(tri.p1, tri.p0), e2 = certified::diff3(tri.p2, tri.p0);
    const certified::ExpVec3 n = cross(e1, e2);
    N = dot(certified::diff3(tri.p0, r.o), n);
    D = dot(certified::exact3(r.d), n);
  };
  // side(lo, hi): sign of t - (lo + hi) / 2 for adjacent doubles lo < hi (exact t = N / D).
  auto side = [&](double lo, double hi) -> std::optional<int> {
    const double half = (hi - lo) * 0.5;  // exact: adjacent normal doubles
    if (sdb && *sdb != 0) {
      const auto sb = certified::sign(Nb - Bounded(lo) * Db - Bounded(half) * Db);
      if (sb) return *sb * *sdb;
    }
    exact_parts();
    if (N->bad || D->bad || D->n == 0) return std::nullopt;
    Expansion m(lo);
    m.grow(half);
    const Expansion sx = *N - m * *D;
    if (sx.bad) return std::nullopt;
    return sx.sign() * D->sign();
  };
  const double lo = next_down(t0), hi = next_up(t0);
  const auto up = side(t0, hi);
  if (!up) return std::nullopt;
  if (*up > 0) return hi;  // t above the midpoint to next: next (t0 is within 1 ulp)
  if (*up == 0) return (std::bit_cast<std::uint64_t>(hi) & 1) ? t0 : hi;  // tie: even
  const auto down = side(lo, t0);
  if (!down) return std::nullopt;
  if (*down < 0) return lo;
  if (*down == 0) return (std::bit_cast<std::uint64_t>(lo) & 1) ? t0 : lo;
  return t0;
}

/// The exact contact of a ray with one triangle: the class from the certified filter (exact; GMP
/// where it cannot decide), t correctly rounded by round_t, exact::intersect for what is left
/// (coplanar ranges, extreme magnitudes).
struct ExactContact {
  Contact1 k;
  Contact contact = Contact::miss;
};
ExactContact exact_contact(const Ray<double>& r, const Triangle<double>& tri) {
  const TriangleHit<double> h = certified::intersect(r, tri);
  switch (h.contact) {
    case Contact::interior: case Contact::edge: case Contact::vertex:
      if (h.t > 0) {
        if (const auto rt = round_t(r, tri, h.t)) return {{Contact1::point, *rt}, h.contact};
      }
      break;
    case Contact::coplanar: break;
    default: return {{}, h.contact};
  }
  const TriangleHit<double> x = exact::intersect(r, tri);
  return {contact_of(x), x.contact};
}

/// Adds `part` into `total`, counter by counter (max_ulps: the larger).
void add_counts(CasterCounts& total, const CasterCounts& part) {
  for (const CasterCounter& counter : kCasterCounters) {
    if (!counter.member) continue;
    std::uint64_t& into = total.*counter.member;
    const std::uint64_t from = part.*counter.member;
    into = counter.maximum ? std::max(into, from) : into + from;
  }
}

struct Tally {
  CasterTally c;
  std::vector<std::size_t> set_rays, set_findings, set_false_miss;
  std::vector<CasterReproducer> reps;
};

}  // namespace

struct CasterJudge::State {
  std::vector<Vec3<double>> v;
  std::vector<std::array<std::uint32_t, 3>> tri;
  std::string name;
  MeshCaster<cast::Certified> caster;

  State(const CasterMesh& m)
      : v(m.vertices.begin(), m.vertices.end()), tri(m.triangles.begin(), m.triangles.end()), name(m.name),
        caster(VertexArray(reinterpret_cast<const double*>(v.data()), v.size()),
               IndexArray{tri.empty() ? nullptr : tri.data()->data(), tri.size()}) {}

  [[nodiscard]] Triangle<double> triangle(std::size_t i) const { return {v[tri[i][0]], v[tri[i][1]], v[tri[i][2]]}; }
};

CasterJudge::CasterJudge(const CasterMesh& mesh) : s_(std::make_unique<State>(mesh)) {}
CasterJudge::~CasterJudge() = default;
CasterJudge::CasterJudge(CasterJudge&&) noexcept = default;
CasterJudge& CasterJudge::operator=(CasterJudge&&) noexcept = default;

CasterTally CasterJudge::judge(const CasterRays& rays, std::span<const CasterAnswer> answers,
                               const CasterCheckOptions& opt) const {
  if (answers.size() != rays.rays.size() || rays.set.size() != rays.rays.size())
    throw std::invalid_argument(fmt::format("judge: {} answers for {} rays", answers.size(), rays.rays.size()));
  const State& s = *s_;
  const std::size_t nsets = rays.names.size();
  const bool f32 = opt.precision == CasterPrecision::float32;
  const auto ntri = static_cast<std::int64_t>(s.tri.size());

  auto judge_range = [&](std::size_t begin, std::size_t end, Tally& T) {
    CasterTally& c = T.c;
    T.set_rays.assign(nsets, 0);
    T.set_findings.assign(nsets, 0);
    T.set_false_miss.assign(nsets, 0);
    // Reproducers kept per kind in this chunk: the first opt.reproducers of each kind over all
    // chunks (in ray order) are among them; the rest are never formatted.
    std::vector<std::pair<std::string_view, std::size_t>> kept;
    auto keep = [&](std::string_view kind) {
      for (auto& [k, n] : kept)
        if (k == kind) return n++ < opt.reproducers;
      kept.emplace_back(kind, 1);
      return opt.reproducers > 0;
    };
    std::vector<MeshHit> near;
    std::vector<double> near_t;  // correctly rounded t of each near crossing (when more than one)
    for (std::size_t i = begin; i < end; ++i) {
      const Ray<double>& r = rays.rays[i];
      const CasterAnswer& a = answers[i];
      const std::size_t set = rays.set[i];
      ++T.set_rays[set];
      const std::string& set_name = rays.names[set];
      auto caster_text = [&] {
        if (a.failed) return std::string("failed");
        return fmt::format("tri {} t {}", a.triangle, num(a.t));
      };
      // exact_text and caster_answer: callables giving the text, called only for a kept reproducer.
      auto finding = [&](std::size_t& counter, const char* kind, auto&& exact_text, auto&& caster_answer) {
        ++counter;
        ++T.set_findings[set];
        if (!keep(kind)) return;
        T.reps.push_back({kind, i,
                          fmt::format("{} set={} mesh={} ray {} exact: {} caster: {}", kind, set_name, s.name,
                                      ray_text(r), exact_text(), caster_answer())});
      };
      auto text = [](const char* t) { return [t] { return std::string(t); }; };
      ++c.rays;
      if (!r.valid()) {
        ++c.invalid_rays;
        if (a.failed) finding(c.invalid_failures, "invalid-ray-failure", text("invalid"), caster_text);
        else if (a.triangle != -1 || a.any == 1) finding(c.invalid_hit, "invalid-ray-hit", text("invalid"), caster_text);
        continue;
      }
      if (a.failed) {
        finding(c.caster_failures, "caster-failure", text("-"), text("failed"));
        continue;
      }
      const MeshHit e = s.caster.closest(r, kPositive);
      // The exact first crossing: every crossing whose certified t is within 4 ulps of the winner's
      // (certified t values are within 1 ulp of the rounded exact ones, so a triangle crossed first
      // exactly, or tied, is among them). With one such crossing it is the first; with several,
      // their correctly rounded t decide (ties to the lowest triangle number).
      std::uint32_t first = e.triangle;
      bool first_coplanar = e.contact == Contact::coplanar;
      std::optional<double> m;  // the first crossing's correctly rounded t, computed when needed
      near.clear(), near_t.clear();
      auto rounded = [&](const MeshHit& h) {
        std::optional<double> rt;
        if (h.contact != Contact::coplanar) rt = round_t(r, s.triangle(h.triangle), h.t);
        return rt ? *rt : exact_contact(r, s.triangle(h.triangle)).k.t;
      };
      if (e.hit()) {
        double lo = e.t, hi = e.t;
        for (int k = 0; k < 4; ++k) lo = next_down(lo), hi = next_up(hi);
        near = s.caster.all(r, {std::max(lo, kPositive.tmin), hi});
        if (near.size() > 1) {
          double best = kInf;
          for (const MeshHit& h : near) {
            near_t.push_back(rounded(h));
            if (near_t.back() < best || (near_t.back() == best && h.triangle < first))
              best = near_t.back(), first = h.triangle, first_coplanar = h.contact == Contact::coplanar;
          }
          m = best;
        }
      }
      auto first_t = [&] {
        if (!m) m = rounded(e);
        return *m;
      };
      auto exact_text = [&] {
        if (!e.hit()) return std::string("miss");
        return fmt::format("tri {} t {} {}", first, num(first_t()), first_coplanar ? "coplanar" : "crossing");
      };
      if (e.hit()) ++c.hits;
      // Occlusion.
      if (a.any >= 0) {
        ++c.any_rays;
        if (e.hit() && a.any == 0) {
          if (first_coplanar) ++c.any_coplanar_miss;
          else finding(c.any_false_miss, "any-false-miss", exact_text, text("any 0"));
        } else if (!e.hit() && a.any == 1) {
          if (!s.caster.any(r, {0, kInf})) finding(c.any_false_hit, "any-false-hit", exact_text, text("any 1"));
        }
      }
      // Closest.
      const bool garbage = std::isnan(a.t) || a.triangle < -1 || a.triangle >= ntri ||
                           (a.triangle == -1 && !(a.t == kInf)) || (a.triangle >= 0 && !(a.t >= 0 && a.t < kInf));
      if (garbage) {
        finding(c.garbage, "garbage", exact_text, caster_text);
        continue;
      }
      const bool c_hit = a.triangle >= 0;
      if (!e.hit() && !c_hit) continue;
      if (!c_hit) {
        if (first_coplanar) ++c.coplanar_miss;
        else finding(c.false_miss, "false-miss", exact_text, caster_text), ++T.set_false_miss[set];
        continue;
      }
      const auto claimed = static_cast<std::uint32_t>(a.triangle);
      if (claimed == first && e.hit()) {
        // The first crossing's triangle: t judged unless coplanar.
        if (first_coplanar) continue;
        // The reference in the caster's precision, from the certified t (within 1 ulp of the
        // rounded exact t) where that decides it, else from the rounded exact t.
        std::uint64_t d = 0;
        bool exact_d = false;
        const double tc = near_t.empty() ? e.t : first_t();
        if (m) {
          exact_d = true;
          d = f32 ? ulp_distance(static_cast<float>(a.t), static_cast<float>(*m)) : ulp_distance(a.t, *m);
        } else if (f32) {
          const float fc = static_cast<float>(tc);
          if (static_cast<float>(next_down(tc)) == fc && static_cast<float>(next_up(tc)) == fc) {
            exact_d = true;
            d = ulp_distance(static_cast<float>(a.t), fc);
          }
        } else {
          const std::uint64_t d0 = ulp_distance(a.t, tc);  // the true distance is within 1 of it
          if (d0 >= 3 && d0 + 1 <= c.max_ulps) exact_d = true, d = d0;  // over 1 ulp, and not a new maximum
        }
        if (!exact_d) {
          const double t_ref = first_t();
          d = f32 ? ulp_distance(static_cast<float>(a.t), static_cast<float>(t_ref)) : ulp_distance(a.t, t_ref);
        }
        c.max_ulps = std::max(c.max_ulps, d);
        if (d > 1)
          finding(c.t_over_1ulp, "t-error", exact_text, [&] {
            const double t_ref = first_t();
            const std::uint64_t dd =
                f32 ? ulp_distance(static_cast<float>(a.t), static_cast<float>(t_ref)) : ulp_distance(a.t, t_ref);
            return caster_text() + fmt::format(" ({} ulps of {})", dd, f32 ? "float" : "double");
          });
        continue;
      }
      // Another triangle: among the near crossings, or tested exactly.
      Contact1 k;
      ExactContact hc;
      std::size_t at = near.size();
      for (std::size_t j = 0; j < near.size(); ++j)
        if (near[j].triangle == claimed) at = j;
      if (at < near.size()) {
        k = {near[at].contact == Contact::coplanar ? Contact1::coplanar : Contact1::point,
             near_t.empty() ? rounded(near[at]) : near_t[at]};
      } else {
        hc = exact_contact(r, s.triangle(claimed));
        k = hc.k;
      }
      if (k.kind == Contact1::origin && a.t == 0) continue;  // the origin lies on the claimed triangle
      if (!e.hit()) {
        finding(c.false_hit, "false-hit", exact_text, caster_text);
        continue;
      }
      if (k.kind == Contact1::none || k.kind == Contact1::origin) {
        finding(c.wrong_triangle, "wrong-triangle", exact_text,
                [&] { return fmt::format("{} (not crossed at t > 0: {})", caster_text(), to_string(hc.contact)); });
        continue;
      }
      const double mt = first_t();
      if (k.t != mt) {
        const std::uint64_t dt = f32 ? ulp_distance(static_cast<float>(k.t), static_cast<float>(mt)) : ulp_distance(k.t, mt);
        if (dt <= 1) ++c.wrong_triangle_near;
        finding(c.wrong_triangle, "wrong-triangle", exact_text,
                [&] { return fmt::format("{} (crossed at t {})", caster_text(), num(k.t)); });
        continue;
      }
      // A triangle tied with the first crossing: t judged against the same exact t.
      if (k.kind != Contact1::point || first_coplanar) continue;
      const std::uint64_t d = f32 ? ulp_distance(static_cast<float>(a.t), static_cast<float>(mt)) : ulp_distance(a.t, mt);
      c.max_ulps = std::max(c.max_ulps, d);
      if (d > 1)
        finding(c.t_over_1ulp, "t-error", exact_text,
                [&] { return caster_text() + fmt::format(" ({} ulps of {})", d, f32 ? "float" : "double"); });
    }
  };

  // Chunks in ray order; each its own tally, merged in order (deterministic reproducers).
  const std::size_t n = rays.rays.size(), chunk = 512;
  const std::size_t chunks = (n + chunk - 1) / chunk;
  std::vector<Tally> parts(chunks);
  auto run = [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& b) {
      for (std::size_t k = b.begin(); k < b.end(); ++k) judge_range(k * chunk, std::min(n, (k + 1) * chunk), parts[k]);
    });
  };
  if (opt.threads > 0) tbb::task_arena(opt.threads).execute(run);
  else run();

  CasterTally out;
  std::vector<std::size_t> set_rays(nsets, 0), set_findings(nsets, 0), set_false_miss(nsets, 0);
  std::vector<std::size_t> kept_per_kind;
  std::vector<std::string> kinds;
  for (Tally& p : parts) {
    add_counts(out, p.c);
    for (std::size_t k = 0; k < nsets && k < p.set_rays.size(); ++k)
      set_rays[k] += p.set_rays[k], set_findings[k] += p.set_findings[k], set_false_miss[k] += p.set_false_miss[k];
    for (CasterReproducer& r : p.reps) {
      const auto it = std::find(kinds.begin(), kinds.end(), r.kind);
      std::size_t at = static_cast<std::size_t>(it - kinds.begin());
      if (it == kinds.end()) kinds.push_back(r.kind), kept_per_kind.push_back(0);
      if (kept_per_kind[at]++ < opt.reproducers) out.reproducers.push_back(std::move(r));
    }
  }
  for (std::size_t k = 0; k < nsets; ++k) out.sets.push_back({rays.names[k], set_rays[k], set_findings[k], set_false_miss[k]});
  out.notes = rays.notes;
  return out;
}

// ---- running a caster ---------------------------------------------------------------------------

void run_caster(const ClosestCaster& closest, const AnyCaster& any, std::span<const Ray<double>> rays,
                std::size_t batch, std::span<CasterAnswer> out, std::string& error) {
  if (out.size() != rays.size()) throw std::invalid_argument("run_caster: output size differs from ray count");
  batch = std::max<std::size_t>(batch, 1);
  std::vector<Vec3<double>> o, d;
  std::vector<double> t;
  std::vector<std::int64_t> tri;
  std::vector<std::uint8_t> occ;
  for (std::size_t at = 0; at < rays.size(); at += batch) {
    const std::size_t n = std::min(batch, rays.size() - at);
    o.resize(n), d.resize(n), t.assign(n, kNaN<double>), tri.assign(n, -2), occ.assign(n, 2);
    for (std::size_t k = 0; k < n; ++k) o[k] = rays[at + k].o, d[k] = rays[at + k].d;
    bool failed = false;
    try {
      closest(o, d, t, tri);
    } catch (const std::exception& e) {
      failed = true;
      if (error.empty()) error = e.what();
    } catch (...) {
      failed = true;
      if (error.empty()) error = "unknown exception";
    }
    bool any_failed = false;
    if (any) {
      try {
        any(o, d, occ);
      } catch (const std::exception& e) {
        any_failed = true;
        if (error.empty()) error = e.what();
      } catch (...) {
        any_failed = true;
      }
    }
    for (std::size_t k = 0; k < n; ++k) {
      CasterAnswer& a = out[at + k];
      a.t = t[k], a.triangle = tri[k], a.failed = failed || any_failed;
      a.any = any && !any_failed ? static_cast<std::int8_t>(occ[k] ? 1 : 0) : std::int8_t(-1);
    }
  }
}

CasterTally check_caster(const ClosestCaster& closest, const CasterMesh& mesh, const CasterCheckOptions& opt,
                         const AnyCaster& any) {
  const CasterRays rays = caster_rays(mesh, opt);
  std::vector<CasterAnswer> answers(rays.rays.size());
  std::string error;
  run_caster(closest, any, rays.rays, opt.batch, answers, error);
  CasterTally c = CasterJudge(mesh).judge(rays, answers, opt);
  if (!error.empty()) c.notes.push_back("the caster threw: " + error);
  return c;
}

CasterTally check_caster(const ClosestCaster& closest, const CasterMesh& mesh, std::span<const Ray<double>> user_rays,
                         const CasterCheckOptions& opt, const AnyCaster& any) {
  CasterRays rays;
  rays.rays.assign(user_rays.begin(), user_rays.end());
  rays.set.assign(rays.rays.size(), 0);
  rays.names = {"user"};
  std::vector<CasterAnswer> answers(rays.rays.size());
  std::string error;
  run_caster(closest, any, rays.rays, opt.batch, answers, error);
  CasterTally c = CasterJudge(mesh).judge(rays, answers, opt);
  if (!error.empty()) c.notes.push_back("the caster threw: " + error);
  return c;
}

std::string summary_text(const CasterTally& tally) {
  std::string text;
  for (const CasterCounter& counter : kCasterCounters)
    if (shown(tally, counter)) text += fmt::format("{:<18} {}\n", text_label(counter), count_of(tally, counter));
  for (const auto& set : tally.sets)
    text += fmt::format("set {:<10} rays {:>7}  findings {:>7}  false_miss {}\n", set.set, set.rays, set.findings,
                        set.false_miss);
  for (const auto& note : tally.notes) text += "note: " + note + "\n";
  for (const auto& reproducer : tally.reproducers) text += reproducer.line + "\n";
  return text;
}

}  // namespace rayproof::verify
