#include "light/render_light.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

#include "gen/rng.h"
#include "rayproof/certified/intersect.h"

namespace rayproof::light {

namespace {

using V = Vec3<double>;
constexpr double kTmin = std::numeric_limits<double>::denorm_min();  // crossings at t > 0
constexpr double kAlbedo = 0.75, kAmbient = 0.03;

/// The hit point, its distance bound from the surface and the surface normal, per primitive kind.
SurfacePoint<double> surface_at(const scene::Scene& s, std::uint32_t id, const Ray<double>& ray, const CastHit& h) {
  std::uint32_t k = 0;
  const V p = ray.at(h.t);
  switch (s.kind_of(id, k)) {
    case scene::PrimKind::triangle: {
      const Triangle<double> t = s.triangle(k);
      const V nrm = cross(t.p1 - t.p0, t.p2 - t.p0);
      if (std::isfinite(h.b1) && std::isfinite(h.b2)) {
        // pbrt-v4: sum b_i v_i, error gamma(7) sum |b_i v_i| per coordinate, along |n|; floor
        // gamma(2) max |p_i| (see light/spawn_mesh.cpp).
        const double b0 = 1 - h.b1 - h.b2;
        const V q = b0 * t.p0 + h.b1 * t.p1 + h.b2 * t.p2;
        auto a = [](V v) { return V{std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}; };
        const V err = gamma<double>(7) * (a(b0 * t.p0) + a(h.b1 * t.p1) + a(h.b2 * t.p2));
        const V n = normalize(nrm);
        const double floor = gamma<double>(2) * std::max({std::fabs(q.x), std::fabs(q.y), std::fabs(q.z)});
        return {q, std::max(dot(a(n), err), floor), n};
      }
      return surface_point_on_plane(reproject_to_plane(p, t.p0, nrm), t.p0, nrm);
    }
    case scene::PrimKind::sphere: {
      const auto& sp = s.spheres[k];
      return surface_point_on_sphere(reproject_to_sphere(p, sp.center, sp.radius), sp.center, sp.radius);
    }
    case scene::PrimKind::disk: {
      const auto& d = s.disks[k];
      return surface_point_on_plane(reproject_to_plane(p, d.center, d.normal), d.center, d.normal);
    }
    case scene::PrimKind::box: {
      const auto& b = s.boxes[k];
      int axis = 0, side = 0;
      double best = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a)
        for (int sd = 0; sd < 2; ++sd) {
          const double dist = std::fabs(p[std::size_t(a)] - (sd ? b.hi[std::size_t(a)] : b.lo[std::size_t(a)]));
          if (dist < best) best = dist, axis = a, side = sd;
        }
      V q = p, n{};
      q[std::size_t(axis)] = side ? b.hi[std::size_t(axis)] : b.lo[std::size_t(axis)];  // on the face's plane exactly
      n[std::size_t(axis)] = side ? 1 : -1;
      return surface_point_on_plane(q, q, n);
    }
    case scene::PrimKind::ellipsoid: {
      // First order: |f(p)| / |grad f| for f = sum ((p - c)_i / a_i)^2 - 1, with its rounding, doubled.
      const auto& e = s.ellipsoids[k];
      const V q = div(p - e.center, e.semi_axes);
      const double f = dot(q, q) - 1;
      const V g = 2.0 * div(q, e.semi_axes);
      const double bound = 2 * (std::fabs(f) + gamma<double>(8) * (dot(q, q) + 1)) / length(g);
      return {p, bound, normalize(g)};
    }
  }
  return {p, 0, {0, 1, 0}};
}

bool meets(const Hit<double>& h) {
  if (h.contact == Contact::coplanar) return true;
  if (h.contact == Contact::miss || h.contact == Contact::behind || h.contact == Contact::parallel ||
      h.contact == Contact::invalid || h.contact == Contact::degenerate)
    return false;
  return (h.t > 0) || (h.t2 > 0);
}

V fl(V v) { return {double(float(v.x)), double(float(v.y)), double(float(v.z))}; }
double fl(double x) { return double(float(x)); }

/// Exactly whether the ray meets primitive `id` at t > 0 (rayproof::certified::intersect); with
/// `as_float`, the primitive rounded to float as float-input methods see it.
bool meets_own(const scene::Scene& s, std::uint32_t id, const Ray<double>& r, bool as_float) {
  std::uint32_t k = 0;
  auto v = [&](V x) { return as_float ? fl(x) : x; };
  auto d = [&](double x) { return as_float ? fl(x) : x; };
  switch (s.kind_of(id, k)) {
    case scene::PrimKind::triangle: {
      const Triangle<double> t = s.triangle(k);
      const TriangleHit<double> h = certified::intersect(r, Triangle<double>{v(t.p0), v(t.p1), v(t.p2)});
      return meets(Hit<double>{h.contact, h.t, h.t2});
    }
    case scene::PrimKind::sphere: return meets(certified::intersect(r, Sphere<double>{v(s.spheres[k].center), d(s.spheres[k].radius)}));
    case scene::PrimKind::ellipsoid:
      return meets(certified::intersect(r, Ellipsoid<double>{v(s.ellipsoids[k].center), v(s.ellipsoids[k].semi_axes)}));
    case scene::PrimKind::disk:
      return meets(certified::intersect(r, Disk<double>{v(s.disks[k].center), v(s.disks[k].normal), d(s.disks[k].radius)}));
    case scene::PrimKind::box: return meets(certified::intersect(r, Box<double>{v(s.boxes[k].lo), v(s.boxes[k].hi)}));
  }
  return false;
}

/// The largest coordinate magnitude a primitive's parameters reach (for the float rounding bound).
double magnitude(const scene::Scene& s, std::uint32_t id) {
  std::uint32_t k = 0;
  auto m = [](V x) { return std::max({std::fabs(x.x), std::fabs(x.y), std::fabs(x.z)}); };
  switch (s.kind_of(id, k)) {
    case scene::PrimKind::triangle: {
      const Triangle<double> t = s.triangle(k);
      return std::max({m(t.p0), m(t.p1), m(t.p2)});
    }
    case scene::PrimKind::sphere: return m(s.spheres[k].center) + s.spheres[k].radius;
    case scene::PrimKind::ellipsoid: return m(s.ellipsoids[k].center) + m(s.ellipsoids[k].semi_axes);
    case scene::PrimKind::disk: return m(s.disks[k].center) + s.disks[k].radius;
    case scene::PrimKind::box: return std::max(m(s.boxes[k].lo), m(s.boxes[k].hi));
  }
  return 0;
}

V tint(const scene::Scene& s, std::uint32_t id) {
  std::uint32_t k = 0;
  switch (s.kind_of(id, k)) {
    case scene::PrimKind::triangle: return {0.55, 0.7, 0.95};
    case scene::PrimKind::sphere: return {0.95, 0.5, 0.4};
    case scene::PrimKind::ellipsoid: return {0.5, 0.9, 0.5};
    case scene::PrimKind::box: return {0.9, 0.8, 0.45};
    case scene::PrimKind::disk: return {0.8, 0.8, 0.8};
  }
  return {1, 1, 1};
}

/// The certified origin toward `target`: the point moved ulp by ulp (of T) along the normal's signs
/// (toward the light's side) until the segment's ray no longer meets its own primitive (as T's
/// methods see it); after 64 steps, the error-bounded origin (`fell_back`).
template <class T>
V certified_origin(const scene::Scene& s, std::uint32_t id, const SurfacePoint<T>& sp, V target, bool& fell_back) {
  const bool as_float = std::is_same_v<T, float>;
  const Vec3<T> side = dot(Vec3<T>{T(target.x), T(target.y), T(target.z)} - sp.p, sp.n) < 0 ? -sp.n : sp.n;
  Vec3<T> o = sp.p;
  for (int step = 0; step <= 64; ++step) {
    const V od{double(o.x), double(o.y), double(o.z)};
    if (!meets_own(s, id, {od, target - od}, as_float)) return fell_back = false, od;
    for (std::size_t i = 0; i < 3; ++i) {
      if (side[i] > 0) o[i] = next_up(o[i]);
      else if (side[i] < 0) o[i] = next_down(o[i]);
    }
  }
  fell_back = true;
  const Vec3<T> e = offset_ray_origin(sp, Vec3<T>{T(target.x), T(target.y), T(target.z)} - sp.p);
  return {double(e.x), double(e.y), double(e.z)};
}

/// The surface point as a float-input method sees it: p rounded to float, the bound grown by the
/// rounding of p and of the primitive's parameters (gamma_float(6) (max |p_i| + the primitive's
/// magnitude)), rounded up.
SurfacePoint<float> to_float(const SurfacePoint<double>& sp, double prim_magnitude) {
  const double pm = std::max({std::fabs(sp.p.x), std::fabs(sp.p.y), std::fabs(sp.p.z)});
  const double bound = (sp.distance_bound + double(gamma<float>(6)) * (pm + prim_magnitude)) * (1 + 1e-6);
  const Vec3<float> n{float(sp.n.x), float(sp.n.y), float(sp.n.z)};
  return {{float(sp.p.x), float(sp.p.y), float(sp.p.z)}, next_up(float(bound)), n};
}

struct Shadow {
  std::size_t pixel;
  std::uint32_t own;
  V contribution;  ///< the estimator's weight times the light's emission, per channel
};

/// Whether the segment is blocked, skipping crossings of primitive `skip` (kNoTriangle: none).
bool blocked_skipping(const SceneCaster& c, const Ray<double>& r, const CastHit& first, std::uint32_t skip) {
  if (!first.hit()) return false;
  if (first.triangle != skip) return true;
  for (const CastHit& x : c.all(r, {kTmin, 1}))
    if (x.triangle != skip) return true;
  return false;
}

}  // namespace

LightResult render_lit(const scene::Scene& s, const SceneCaster& caster, int width, int height,
                       std::span<const Ray<double>> rays, std::span<const CastHit> hits, const LightOptions& opt) {
  LightResult out;
  const std::size_t npix = std::size_t(width) * std::size_t(height);
  std::vector<V> radiance(npix, V{0, 0, 0}), albedo(npix, V{0, 0, 0});
  std::vector<Shadow> shadows;
  std::vector<Ray<double>> shadow_rays, reference_rays;
  const double nl = double(s.lights.size());
  for (std::size_t p = 0; p < npix; ++p) {
    const CastHit& h = hits[p];
    if (!h.hit()) continue;
    ++out.hit_pixels;
    const std::uint32_t id = h.triangle;
    const SurfacePoint<double> sp = surface_at(s, id, rays[p], h);
    const V n_view = dot(sp.n, rays[p].d) > 0 ? -sp.n : sp.n;
    albedo[p] = kAlbedo * tint(s, id);
    gen::Rng rng(opt.seed ^ (0x9e3779b97f4a7c15ULL * (p + 1)));
    for (int k = 0; k < opt.shadow_rays; ++k) {
      const scene::DiskLight& light = s.lights[std::min(s.lights.size() - 1, std::size_t(rng.unit() * nl))];
      const Disk<double>& d = light.disk;
      const V ln = normalize(d.normal);
      const V a = normalize(cross(ln, std::fabs(ln.x) < 0.9 ? V{1, 0, 0} : V{0, 1, 0}));
      const V b = cross(ln, a);
      const double u1 = rng.unit(), u2 = rng.unit();
      V y;
      double weight = 0;  // f / L: the estimator's sample of E / L
      const double dist_c = length(d.center - sp.p);
      if (opt.solid_angle && dist_c > d.radius) {
        // Uniform in the cone around the disk's bounding sphere.
        const double cos_max = std::sqrt(std::max(0.0, 1 - (d.radius / dist_c) * (d.radius / dist_c)));
        const double ct = 1 - u1 * (1 - cos_max), st = std::sqrt(std::max(0.0, 1 - ct * ct));
        const V axis = (d.center - sp.p) / dist_c;
        const V ta = normalize(cross(axis, std::fabs(axis.x) < 0.9 ? V{1, 0, 0} : V{0, 1, 0}));
        const V tb = cross(axis, ta);
        const double phi = 2 * std::numbers::pi * u2;
        const V w = ct * axis + (st * std::cos(phi)) * ta + (st * std::sin(phi)) * tb;
        const double den = dot(w, ln);
        if (den >= 0) continue;  // parallel to the disk or toward its back face
        const double t = dot(d.center - sp.p, ln) / den;
        y = sp.p + t * w;
        if (!(t > 0) || length(y - d.center) > d.radius) continue;  // misses the disk: f = 0
        const double cos_s = dot(w, n_view);
        if (cos_s <= 1e-6) continue;
        weight = cos_s * 2 * std::numbers::pi * (1 - cos_max);
      } else {
        const double rho = d.radius * std::sqrt(u1), phi = 2 * std::numbers::pi * u2;
        y = d.center + (rho * std::cos(phi)) * a + (rho * std::sin(phi)) * b;
        const V w = y - sp.p;
        const double d2 = dot(w, w), len = std::sqrt(d2);
        const double cos_s = dot(w, n_view) / len, cos_l = -dot(w, ln) / len;
        if (cos_s <= 1e-6 || cos_l <= 0) continue;
        weight = cos_s * cos_l * std::numbers::pi * d.radius * d.radius / d2;
      }
      const double scale = weight * nl / opt.shadow_rays;
      const V contribution{scale * light.emission.x, scale * light.emission.y, scale * light.emission.z};
      V o;
      bool fell_back = false;
      if (opt.float_inputs) {
        const SurfacePoint<float> spf = to_float(sp, magnitude(s, id));
        if (opt.spawn == SpawnStrategy::certified) {
          o = certified_origin(s, id, spf, y, fell_back);
        } else {
          const Vec3<float> wf{float(y.x - sp.p.x), float(y.y - sp.p.y), float(y.z - sp.p.z)};
          const Vec3<float> of = spawn_ray(spf, wf, opt.spawn, float(opt.epsilon)).o;
          o = {double(of.x), double(of.y), double(of.z)};
        }
      } else if (opt.spawn == SpawnStrategy::certified) {
        o = certified_origin(s, id, sp, y, fell_back);
      } else {
        o = spawn_ray(sp, y - sp.p, opt.spawn, opt.epsilon).o;
      }
      if (fell_back) ++out.certified_fallbacks;
      shadows.push_back({p, id, contribution});
      shadow_rays.push_back({o, y - o});
      if (opt.exact) {
        bool fb = false;
        const V ro = certified_origin(s, id, sp, y, fb);
        reference_rays.push_back({ro, y - ro});
      }
    }
  }
  out.shadow_rays = shadows.size();
  std::vector<CastHit> first(shadow_rays.size());
  caster.closest(shadow_rays, first, opt.threads, {kTmin, 1});
  std::vector<std::uint8_t> acne(npix, 0), visible(shadows.size(), 0);
  for (std::size_t i = 0; i < shadows.size(); ++i) {
    const Shadow& sh = shadows[i];
    bool blocked;
    if (opt.spawn == SpawnStrategy::certified) {
      // The primitive it leaves is classified exactly (not met, unless the walk gave up).
      const bool own = meets_own(s, sh.own, shadow_rays[i], opt.float_inputs);
      if (own) ++out.acne_rays, acne[sh.pixel] = 1;
      blocked = own || blocked_skipping(caster, shadow_rays[i], first[i], sh.own);
    } else {
      blocked = first[i].hit();
      if (blocked && first[i].triangle == sh.own) ++out.acne_rays, acne[sh.pixel] = 1;
    }
    visible[i] = !blocked;
    if (!blocked) radiance[sh.pixel] = radiance[sh.pixel] + sh.contribution;
  }
  out.acne_pixels = std::uint64_t(std::count(acne.begin(), acne.end(), std::uint8_t(1)));

  out.rgb.assign(npix * 3, 0);
  for (std::size_t p = 0; p < npix; ++p) {
    if (!hits[p].hit()) {
      out.rgb[3 * p] = 30, out.rgb[3 * p + 1] = 30, out.rgb[3 * p + 2] = 40;
      continue;
    }
    for (std::size_t c = 0; c < 3; ++c) {
      const double v = albedo[p][c] * (radiance[p][c] / std::numbers::pi + kAmbient);
      out.rgb[3 * p + c] = static_cast<std::uint8_t>(std::clamp(std::pow(std::clamp(v, 0.0, 1.0), 1 / 2.2) * 255 + 0.5, 0.0, 255.0));
    }
  }

  if (opt.exact) {
    std::vector<CastHit> ref(reference_rays.size());
    opt.exact->closest(reference_rays, ref, opt.threads, {kTmin, 1});
    std::vector<std::uint8_t> mark(npix, 0);  // bit 1: false occlusion, bit 2: leak
    for (std::size_t i = 0; i < shadows.size(); ++i) {
      const bool ref_blocked = blocked_skipping(*opt.exact, reference_rays[i], ref[i], shadows[i].own);
      if (!visible[i] && !ref_blocked) ++out.false_occlusions, mark[shadows[i].pixel] |= 1;
      if (visible[i] && ref_blocked) ++out.leaks, mark[shadows[i].pixel] |= 2;
    }
    out.overlay.resize(out.rgb.size());
    for (std::size_t p = 0; p < npix; ++p) {
      std::uint8_t c[3] = {std::uint8_t(out.rgb[3 * p] / 3), std::uint8_t(out.rgb[3 * p + 1] / 3), std::uint8_t(out.rgb[3 * p + 2] / 3)};
      if (mark[p]) ++out.differing_pixels;
      if (mark[p] == 1) c[0] = 255, c[1] = 0, c[2] = 0;
      else if (mark[p] == 2) c[0] = 0, c[1] = 80, c[2] = 255;
      else if (mark[p] == 3) c[0] = 255, c[1] = 0, c[2] = 255;
      std::copy(c, c + 3, out.overlay.begin() + 3 * std::ptrdiff_t(p));
    }
  }
  return out;
}

}  // namespace rayproof::light
