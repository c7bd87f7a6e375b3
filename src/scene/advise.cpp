// rayproof advise, the numbers (see advise.h).
#include "scene/advise.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <cmath>
#include <random>

#include "rayproof/float_util.h"
#include "scene/accel.h"
#include "scene/watertight.h"

namespace rayproof::scene {

namespace {

using Clock = std::chrono::steady_clock;

struct RaySet {
  explicit RaySet(std::string n, std::vector<Ray<double>> r = {}) : name(std::move(n)), rays(std::move(r)) {}
  std::string name;
  std::vector<Ray<double>> rays;
  std::vector<QueryRange> ranges;  ///< one per ray, or one for all
  std::vector<PrimHit> reference;  ///< certified's closest hits
};

QueryRange range_of(const RaySet& s, std::size_t i) { return s.ranges.size() > 1 ? s.ranges[i] : s.ranges[0]; }

/// Every `stride`-th index of n so that at most `cap` remain (cap 0: all).
std::vector<std::size_t> strided(std::size_t n, std::size_t cap) {
  const std::size_t stride = cap && n > cap ? (n + cap - 1) / cap : 1;
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < n; i += stride) out.push_back(i);
  return out;
}

/// Closest hits of `rays[idx]` (all rays when idx is empty) with their ranges, on `threads` threads.
std::vector<PrimHit> cast(const Accel& a, const SceneMethod& m, const RaySet& set, const std::vector<std::size_t>* idx,
                          int threads, double& seconds) {
  std::vector<Ray<double>> rays;
  std::vector<QueryRange> ranges;
  const std::vector<Ray<double>>* use = &set.rays;
  const std::vector<QueryRange>* use_r = &set.ranges;
  if (idx) {
    for (std::size_t i : *idx) rays.push_back(set.rays[i]), ranges.push_back(range_of(set, i));
    if (ranges.size() == 1) ranges.push_back(ranges[0]), rays.push_back(rays[0]);  // keep "one per ray"
    use = &rays, use_r = &ranges;
  }
  std::vector<PrimHit> out(use->size());
  const auto start = Clock::now();
  a.closest_batch(*use, *use_r, [](void* o, std::size_t i, const PrimHit& h) { static_cast<PrimHit*>(o)[i] = h; },
                  out.data(), m, threads);
  seconds += std::chrono::duration<double>(Clock::now() - start).count();
  if (idx && idx->size() == 1) out.resize(1);
  return out;
}

/// The scene's bounds in double: the vertices themselves, and the analytic primitives' float boxes
/// (Scene::bounds() is in float, rounded outward: a mesh at 1e-300 would get a box of 1e-45).
struct DBox {
  static constexpr double kBig = std::numeric_limits<double>::infinity();
  Vec3<double> lo{kBig, kBig, kBig}, hi{-kBig, -kBig, -kBig};
};
DBox double_bounds(const Scene& s) {
  DBox b;
  auto add = [&](const Vec3<double>& p) {
    for (int k = 0; k < 3; ++k) b.lo[k] = std::min(b.lo[k], p[k]), b.hi[k] = std::max(b.hi[k], p[k]);
  };
  for (const auto& v : s.mesh.vertices) add(v);
  if (s.size() > s.mesh.triangles.size()) {
    Scene analytic = s;
    analytic.mesh = {};
    const BvhBox f = analytic.bounds();
    add({f.lo[0], f.lo[1], f.lo[2]}), add({f.hi[0], f.hi[1], f.hi[2]});
  }
  return b;
}

std::vector<Ray<double>> random_rays(const DBox& b, std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> g;
  std::vector<Ray<double>> out(n);
  for (auto& r : out) {
    for (int k = 0; k < 3; ++k) r.o[k] = b.lo[k] + (b.hi[k] - b.lo[k]) * u(rng);
    do r.d = {g(rng), g(rng), g(rng)};
    while (is_zero(r.d));
  }
  return out;
}

/// A point uniformly distributed on a disk.
Vec3<double> sample_disk(const Disk<double>& d, std::mt19937_64& rng) {
  const Vec3<double> n = normalize(d.normal);
  const Vec3<double> a = std::fabs(n.x) < 0.9 ? Vec3<double>{1, 0, 0} : Vec3<double>{0, 1, 0};
  const Vec3<double> e1 = normalize(cross(n, a)), e2 = cross(n, e1);
  std::uniform_real_distribution<double> u(0, 1);
  const double r = d.radius * std::sqrt(u(rng)), phi = 2 * 3.14159265358979323846 * u(rng);
  return d.center + (r * std::cos(phi)) * e1 + (r * std::sin(phi)) * e2;
}

int kind_index(io::Kind k) {
  switch (k) {
    case io::Kind::triangle: return 0;
    case io::Kind::sphere: return 1;
    case io::Kind::ellipsoid: return 2;
    case io::Kind::disk: return 3;
    case io::Kind::box: return 4;
    default: return -1;
  }
}

/// The scene's kinds as the registry names them.
std::vector<io::Kind> scene_kinds(const SceneAnalysis& a) {
  std::vector<io::Kind> k;
  if (a.triangles) k.push_back(io::Kind::triangle);
  if (a.spheres) k.push_back(io::Kind::sphere);
  if (a.ellipsoids) k.push_back(io::Kind::ellipsoid);
  if (a.disks) k.push_back(io::Kind::disk);
  if (a.boxes) k.push_back(io::Kind::box);
  return k;
}

/// volume_centroid() computed on the mesh scaled by a power of 2 that brings its largest coordinate
/// near 1 (the signed volumes are cubes of coordinates: they overflow or underflow in place), then
/// scaled back.
Vec3<double> scaled_centroid(const mesh::Mesh& m) {
  double big = 0;
  for (const auto& v : m.vertices) big = std::max({big, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  if (!(big > 0) || !std::isfinite(big)) return volume_centroid(m);
  const int e = std::ilogb(big);
  mesh::Mesh scaled = m;
  for (auto& v : scaled.vertices) v = {std::ldexp(v.x, -e), std::ldexp(v.y, -e), std::ldexp(v.z, -e)};
  const Vec3<double> c = volume_centroid(scaled);
  return {std::ldexp(c.x, e), std::ldexp(c.y, e), std::ldexp(c.z, e)};
}

/// x rounded to float, beyond float's range: infinity (the conversion itself would be undefined).
float to_float(double x) {
  if (std::fabs(x) > double(std::numeric_limits<float>::max())) return std::copysign(std::numeric_limits<float>::infinity(), float(x > 0 ? 1 : -1));
  return float(x);
}

/// Whether certified also crosses primitive `prim` at exactly the reference t (a tie at a shared edge or vertex).
bool is_tie(const Accel& a, const SceneMethod& certified, const Ray<double>& r, const PrimHit& ref, std::uint32_t prim) {
  for (const PrimHit& h : a.all(r, certified, {ref.t, ref.t}))
    if (h.prim == prim) return true;
  return false;
}

/// The t tolerance per kind (triangle, sphere, ellipsoid, disk, box); none: t error not counted.
using Tolerances = std::array<std::optional<std::uint64_t>, 5>;

/// A primitive's kind as kind_index numbers it.
std::size_t kind_slot(const Scene& s, std::uint32_t prim) {
  std::uint32_t local;
  switch (s.kind_of(prim, local)) {
    case PrimKind::triangle: return 0;
    case PrimKind::sphere: return 1;
    case PrimKind::ellipsoid: return 2;
    case PrimKind::disk: return 3;
    case PrimKind::box: return 4;
  }
  return 0;
}

void compare(const Scene& s, const Accel& a, const SceneMethod& certified, const RaySet& set,
             const std::vector<std::size_t>* idx, const std::vector<PrimHit>& got, double same_point,
             const Tolerances& tol, MethodTally& m) {
  const bool leak = set.name == "leak";
  for (std::size_t k = 0; k < got.size(); ++k) {
    const std::size_t i = idx ? (*idx)[k] : k;
    const PrimHit& ref = set.reference[i];
    const PrimHit& h = got[k];
    ++m.rays;
    m.leak_rays += leak;
    const bool rh = ref.prim != PrimHit::kNoPrim, mh = h.prim != PrimHit::kNoPrim;
    if (!rh && !mh) continue;
    if (!rh) {
      ++m.false_hits;
      continue;
    }
    if (!mh) {
      ++(leak ? m.leaks : m.false_misses);
      continue;
    }
    const std::uint64_t u = m.float_precision ? ulp_distance(to_float(h.t), to_float(ref.t)) : ulp_distance(h.t, ref.t);
    if (h.prim != ref.prim) {
      // Another primitive: at the same point (the two hit points within `same_point` along the ray:
      // a neighbour meeting there, as at a shared edge or vertex), or one certified also crosses at
      // exactly that t; else a wrong one.
      const double gap = std::fabs(h.t - ref.t) * length(set.rays[i].d);
      if (!(gap <= same_point) && !is_tie(a, certified, set.rays[i], ref, h.prim)) {
        ++(leak ? m.leak_wrong_prims : m.wrong_prims);
        continue;
      }
      ++m.ties;
    } else if (h.contact != ref.contact) {
      ++m.wrong_class;
    }
    ++m.t_compared;
    m.max_ulps = std::max(m.max_ulps, u);
    const auto& t_tol = tol[kind_slot(s, ref.prim)];
    m.t_over += t_tol && u > *t_tol;
  }
}

}  // namespace

double same_point_distance(const SceneAnalysis& a) { return std::ldexp(a.max_abs, -20); }

std::optional<std::string> cheapest_error_free(const std::vector<MethodTally>& methods, bool count_leak_grazes) {
  const MethodTally* best = nullptr;
  for (int pass = 0; pass < 2 && !best; ++pass)
    for (const auto& m : methods)
      if (m.error_free(count_leak_grazes) && (pass == 1 || m.compiled) && (!best || m.mrays() > best->mrays())) best = &m;
  if (!best) return std::nullopt;
  return best->name;
}

AdviseResult advise(const Scene& s, const MethodRegistry& reg, const AdviseOptions& opt) {
  const auto t0 = Clock::now();
  auto say = [&](const std::string& line) {
    if (opt.progress) opt.progress(line);
  };
  if (s.size() == 0) throw SceneError("the scene is empty: no triangle and no analytic primitive");
  AdviseResult res;
  say("analysing the geometry");
  res.analysis = analyse_scene(s, opt.sliver_aspect);
  const SceneAnalysis& an = res.analysis;

  // Methods first, so that an unknown name fails before any work.
  std::vector<std::string> names = opt.methods;
  if (names.empty()) {
    names = compiled_scene_method_names(reg);
    for (const auto& m : reg.all())
      if (m.name != "exact" && std::find(names.begin(), names.end(), m.name) == names.end()) names.push_back(m.name);
  }
  if (std::find(names.begin(), names.end(), "certified") == names.end()) names.push_back("certified");
  std::vector<SceneMethod> methods;
  for (const auto& n : names) methods.push_back(find_scene_method(n, reg));
  const SceneMethod certified = find_scene_method("certified", reg);
  const SceneMethod exact = find_scene_method("exact", reg);

  say("building the BVH");
  const Accel accel(s);

  // The scene's rays.
  std::vector<RaySet> sets;
  {
    RaySet p("primary");
    const Camera cam = s.camera ? *s.camera : default_camera(s, 640, 480);
    const double pixels = double(cam.width()) * cam.height();
    const int step = std::max(1, int(std::ceil(std::sqrt(pixels / double(std::max<std::size_t>(1, opt.rays))))));
    for (int j = step / 2; j < cam.height(); j += step)
      for (int i = step / 2; i < cam.width(); i += step) p.rays.push_back(cam.generate(i, j));
    p.ranges = {QueryRange{}};
    sets.push_back(std::move(p));
  }
  if (an.closed_components) {
    // Leak rays of at most `rays` closed components, `rays` / components targets each (at least 1).
    RaySet l("leak");
    const auto meshes = closed_component_meshes(s, an, opt.rays);
    const std::size_t per = std::max<std::size_t>(1, opt.rays / meshes.size());
    for (const auto& m : meshes) {
      const auto rays = leak_rays(scaled_centroid(m), leak_targets(m, per));
      for (const auto& r : rays)
        if (r.valid()) l.rays.push_back(r);
    }
    res.leak_components = meshes.size();
    l.ranges = {QueryRange{}};
    if (!l.rays.empty()) sets.push_back(std::move(l));
  }
  {
    RaySet r("random", random_rays(double_bounds(s), opt.rays, opt.seed));
    r.ranges = {QueryRange{}};
    sets.push_back(std::move(r));
  }
  // The reference: certified on every ray (its time is its speed).
  double cert_seconds = 0;
  for (auto& set : sets) {
    say("certified (the reference): " + std::to_string(set.rays.size()) + " " + set.name + " rays");
    set.reference = cast(accel, certified, set, nullptr, opt.threads, cert_seconds);
  }
  if (!s.lights.empty()) {
    // Shadow rays: from a point on a light to each point certified's primary rays hit, the range
    // stopping short of the surface (t < 1 - 2^-16) so that the target itself does not count.
    const RaySet& prim = sets[0];
    RaySet sh("shadow");
    std::mt19937_64 rng(opt.seed ^ 0x5ad0u);
    for (std::size_t i = 0; i < prim.rays.size() && sh.rays.size() < opt.rays; ++i) {
      const PrimHit& h = prim.reference[i];
      if (h.prim == PrimHit::kNoPrim) continue;
      const Vec3<double> p = prim.rays[i].o + h.t * prim.rays[i].d;
      const Vec3<double> from = sample_disk(s.lights[i % s.lights.size()].disk, rng);
      const Ray<double> r{from, p - from};
      if (r.valid()) sh.rays.push_back(r);
    }
    sh.ranges = {QueryRange{0, 1 - 0x1p-16}};
    if (!sh.rays.empty()) {
      say("certified (the reference): " + std::to_string(sh.rays.size()) + " shadow rays");
      sh.reference = cast(accel, certified, sh, nullptr, opt.threads, cert_seconds);
      sets.push_back(std::move(sh));
    }
  }
  for (const auto& set : sets) {
    RaySetInfo info{set.name, set.rays.size()};
    for (std::size_t i = 0; i < set.rays.size(); ++i) {
      info.invalid += !set.rays[i].valid();
      info.reference_hits += set.reference[i].prim != PrimHit::kNoPrim;
    }
    res.sets.push_back(info);
    if (set.name == "leak")
      for (const auto& h : set.reference) res.reference_misses_on_leak_rays += h.prim == PrimHit::kNoPrim;
  }

  // certified against exact on a sample.
  for (const auto& set : sets) {
    if (opt.exact_sample == 0) break;
    say("exact (the check of the reference): " + set.name + " rays");
    const auto idx = strided(set.rays.size(), opt.exact_sample);
    double sec = 0;
    const auto ex = cast(accel, exact, set, &idx, opt.threads, sec);
    for (std::size_t k = 0; k < idx.size(); ++k) {
      const PrimHit& c = set.reference[idx[k]];
      ++res.exact_checked;
      res.exact_agree += c.prim == ex[k].prim && c.contact == ex[k].contact &&
                         (c.prim == PrimHit::kNoPrim || ulp_distance(c.t, ex[k].t) <= 1);
    }
  }

  // Every method against the reference.
  const std::vector<io::Kind> kinds = scene_kinds(an);
  for (std::size_t mi = 0; mi < methods.size(); ++mi) {
    const SceneMethod& sm = methods[mi];
    MethodTally t;
    t.name = sm.name;
    t.compiled = sm.fast != FastKernel::none;
    const Method* rm = sm.generic ? sm.generic : reg.find(sm.name);
    t.float_precision = rm ? rm->precision == Precision::float32 : sm.name.find("float") != std::string::npos;
    // The promise on each of the scene's kinds: one text when they agree, else "kind: text; ...";
    // the t tolerance per kind (the promised ulps, else the options').
    std::vector<std::pair<io::Kind, std::string>> said;
    Tolerances tol;
    for (io::Kind k : kinds) {
      const Promise pr = rm ? rm->promise(k) : Promise{};
      said.emplace_back(k, pr.describe());
      tol[std::size_t(kind_index(k))] = pr.t_ulps ? pr.t_ulps : opt.t_tolerance;
    }
    bool same = true;
    for (const auto& [k, d] : said) same = same && d == said.front().second;
    for (const auto& [k, d] : said) {
      if (same && !t.promise.empty()) break;
      t.promise += (t.promise.empty() ? "" : "; ") + (same ? d : std::string(io::to_string(k)) + ": " + d);
    }
    t.tolerance = tol[std::size_t(kind_index(kinds.front()))];
    for (const auto& x : tol) t.tolerance = x == t.tolerance ? t.tolerance : std::nullopt;
    if (!t.compiled && sm.generic)
      for (io::Kind k : kinds)
        if (!sm.generic->supports(k)) t.unsupported.emplace_back(io::to_string(k));
    for (const auto& set : sets) {
      say(sm.name + " (" + std::to_string(mi + 1) + "/" + std::to_string(methods.size()) + "): " + set.name + " rays");
      if (sm.name == "certified") {
        t.rays += set.rays.size();
        t.leak_rays += set.name == "leak" ? set.rays.size() : 0;
        continue;
      }
      std::vector<std::size_t> idx;
      if (!t.compiled) idx = strided(set.rays.size(), opt.slow_rays);
      const auto got = cast(accel, sm, set, t.compiled ? nullptr : &idx, opt.threads, t.seconds);
      const std::uint64_t before = t.errors();
      compare(s, accel, certified, set, t.compiled ? nullptr : &idx, got, same_point_distance(an), tol, t);
      if (t.errors() > before) t.errors_by_set.emplace_back(set.name, t.errors() - before);
    }
    if (sm.name == "certified") t.seconds = cert_seconds;
    res.methods.push_back(std::move(t));
  }

  // The candidates for the recommendation (compiled, no error but perhaps grazes on leak rays,
  // certified among them) timed again in rounds over the candidates, so that a change in the
  // machine's load falls on all of them, and the fastest run of each kept: 2 rounds more, more (up
  // to max_timing_runs in all) when a run is short (under 0.1 s for the quickest: noise weighs most).
  std::vector<int> extra(methods.size(), 0);
  int rounds = 0;
  for (std::size_t mi = 0; mi < methods.size(); ++mi) {
    const MethodTally& t = res.methods[mi];
    if (!t.compiled || !t.error_free(false)) continue;
    // A run over 5 s (certified on a scene that needs its GMP fallback throughout) is not repeated.
    if (t.seconds > 5) continue;
    extra[mi] = int(std::clamp(std::ceil(0.1 / std::max(t.seconds, 1e-6)), 2.0, std::max(2.0, opt.max_timing_runs - 1.0)));
    rounds = std::max(rounds, extra[mi]);
  }
  for (int rep = 0; rep < rounds; ++rep) {
    say("timing the candidates again (" + std::to_string(rep + 2) + "/" + std::to_string(rounds + 1) + ")");
    for (std::size_t mi = 0; mi < methods.size(); ++mi) {
      MethodTally& t = res.methods[mi];
      if (rep >= extra[mi]) continue;
      double sec = 0;
      for (const auto& set : sets) (void)cast(accel, methods[mi], set, nullptr, opt.threads, sec);
      t.seconds = std::min(t.seconds, sec);
      t.timing_runs = extra[mi] + 1;
    }
  }

  // Which of certified's and robust's paths the rays reach: the registry methods wrapped with
  // counters, on the same BVH and conservative traversal, one thread (the fallback counter is
  // per thread), on a strided sample of each set.
  {
    PathCounts& pc = res.paths;
    const Method* cm = reg.find("certified");
    const Method* rb = reg.find("robust");
    Method cw, rw;
    if (cm) {
      cw = *cm;
      cw.classify = [&pc, cm](const io::Case& c) {
        const int k = kind_index(c.kind);
        const std::uint64_t before = cm->fallbacks ? cm->fallbacks() : 0;
        io::CaseResult r = cm->classify(c);
        if (k >= 0) ++pc.certified_tests[k], pc.certified_fallbacks[k] += (cm->fallbacks ? cm->fallbacks() : 0) > before;
        return r;
      };
    }
    if (rb) {
      rw = *rb;
      rw.classify = [&pc, rb](const io::Case& c) {
        if (c.kind == io::Kind::triangle) {
          const Vec3<double> d{c.v[3], c.v[4], c.v[5]}, p0{c.v[6], c.v[7], c.v[8]}, p1{c.v[9], c.v[10], c.v[11]},
              p2{c.v[12], c.v[13], c.v[14]};
          const Vec3<double> n = cross(p1 - p0, p2 - p0);
          ++pc.robust_tests;
          if (is_zero(n)) ++pc.robust_degenerate;
          else if (dot(d, n) == 0.0) ++pc.robust_parallel;
        }
        return rb->classify(c);
      };
    }
    for (const auto& set : sets) {
      say("path counts: " + set.name + " rays");
      for (std::size_t i : strided(set.rays.size(), opt.slow_rays)) {
        ++pc.rays;
        if (cm) (void)accel.closest(set.rays[i], SceneMethod{"certified", FastKernel::none, &cw, BvhTraversal::conservative}, range_of(set, i));
        if (rb) (void)accel.closest(set.rays[i], SceneMethod{"robust", FastKernel::none, &rw, BvhTraversal::conservative}, range_of(set, i));
      }
    }
  }

  // A triangle-only scene against the same triangles plus one sphere.
  if (opt.compare_kinds && an.triangle_only() && an.triangles > 0) {
    Scene plus = s;
    const DBox b = double_bounds(s);
    const Vec3<double> lo = b.lo, hi = b.hi;
    // The box's largest side (its diagonal could overflow at 1e300).
    const double diag = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, std::numeric_limits<double>::min()});
    plus.spheres.push_back({hi + (0.02 * diag) * Vec3<double>{1, 1, 1}, 0.01 * diag});
    const Accel with_sphere(plus);
    RaySet r("random", random_rays(b, opt.kind_cost_rays ? opt.kind_cost_rays : std::clamp<std::size_t>(opt.rays, 20000, 100000), opt.seed + 1));
    r.ranges = {QueryRange{}};
    res.random_rays_for_kind_cost = r.rays.size();
    for (const char* name : {"float", "robust", "certified"}) {
      say(std::string("triangle-only against one sphere more: ") + name);
      const SceneMethod m = find_scene_method(name, reg);
      KindCost kc{name, 0, 0, 5};
      double warm = 0;
      (void)cast(accel, m, r, nullptr, opt.threads, warm);
      (void)cast(with_sphere, m, r, nullptr, opt.threads, warm);
      if (warm > 2) kc.repeats = 1;  // a slow method (over a second a run): one round of three
      // Triangle-only, with the sphere, triangle-only again: the two triangle-only series measure
      // the noise of the timings themselves.
      for (int rep = 0; rep < kc.repeats; ++rep) {
        double a = 0, w = 0, b = 0;
        (void)cast(accel, m, r, nullptr, opt.threads, a);
        (void)cast(with_sphere, m, r, nullptr, opt.threads, w);
        (void)cast(accel, m, r, nullptr, opt.threads, b);
        const double n = double(r.rays.size()) / 1e6;
        kc.triangles_only = std::max(kc.triangles_only, n / std::max(a, 1e-9));
        kc.with_sphere = std::max(kc.with_sphere, n / std::max(w, 1e-9));
        kc.triangles_only_again = std::max(kc.triangles_only_again, n / std::max(b, 1e-9));
      }
      res.kind_cost.push_back(kc);
    }
  }

  res.recommended = cheapest_error_free(res.methods, true);
  res.recommended_except_grazes = cheapest_error_free(res.methods, false);
  res.t_tolerance = opt.t_tolerance;
  res.same_point = same_point_distance(an);
  res.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return res;
}

}  // namespace rayproof::scene



