#include "light/spawn_count.h"

#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "gen/rng.h"

namespace rayproof::light {

namespace {

constexpr std::array<SpawnStrategy, 4> kStrategies = {SpawnStrategy::none, SpawnStrategy::fixed_epsilon,
                                                      SpawnStrategy::error_bounded, SpawnStrategy::certified};

Vec3<double> random_unit(gen::Rng& rng) {
  for (;;) {
    const double x = rng.sym();
    const double y = rng.sym();
    const double z = rng.sym();
    const double l2 = x * x + y * y + z * z;
    if (l2 > 1e-4 && l2 <= 1) return Vec3<double>{x, y, z} / std::sqrt(l2);
  }
}

/// A point uniform in the disk of radius r around c, perpendicular to unit n.
Vec3<double> in_disk(gen::Rng& rng, Vec3<double> c, Vec3<double> n, double r) {
  const Vec3<double> a = normalize(cross(n, std::fabs(n.x) < 0.9 ? Vec3<double>{1, 0, 0} : Vec3<double>{0, 1, 0}));
  const Vec3<double> b = cross(n, a);
  const double rho = r * std::sqrt(rng.unit());
  const double phi = 2 * std::numbers::pi * rng.unit();
  return c + (rho * std::cos(phi)) * a + (rho * std::sin(phi)) * b;
}

/// The primary case: a primitive at magnitude ~ scale and a ray from outside aimed inside it.
io::Case make_case(io::Kind kind, gen::Rng& rng, double scale) {
  const Vec3<double> c{scale * rng.sym(), scale * rng.sym(), scale * rng.sym()};
  const Vec3<double> n = random_unit(rng);
  const double r = rng.uniform(0.5, 2);
  const double dist = rng.uniform(2, 10);
  io::Case k;
  k.kind = kind;
  Vec3<double> o, target;
  switch (kind) {
    case io::Kind::sphere:
      o = c + (r * dist) * n;
      target = c + (0.9 * r) * random_unit(rng);
      k.v = {o.x, o.y, o.z, target.x - o.x, target.y - o.y, target.z - o.z, c.x, c.y, c.z, r};
      break;
    case io::Kind::plane:
    case io::Kind::disk: {
      const Vec3<double> side = in_disk(rng, c, n, 3 * r);
      o = side + dist * n;
      target = in_disk(rng, c, n, 0.9 * r);
      k.v = {o.x, o.y, o.z, target.x - o.x, target.y - o.y, target.z - o.z, c.x, c.y, c.z, n.x, n.y, n.z,
             kind == io::Kind::disk ? r : 0.0};
      break;
    }
    default: throw std::invalid_argument("spawn counts are for plane, sphere and disk");
  }
  return k;
}

bool primary_hit(const io::CaseResult& r) {
  return (r.contact == Contact::hit || r.contact == Contact::rim || r.contact == Contact::tangent) && r.t && *r.t > 0;
}

/// Any contact of the spawned ray with the surface it leaves at t > 0.
bool self_hit(const io::CaseResult& r) {
  if (r.contact == Contact::coplanar) return true;
  if (r.contact == Contact::miss || r.contact == Contact::behind || r.contact == Contact::parallel) return false;
  return (r.t && *r.t > 0) || (r.t2 && *r.t2 > 0);
}

template <class T>
Vec3<T> vec(const io::Case& c, int at) {
  return {static_cast<T>(c.v[static_cast<std::size_t>(at)]), static_cast<T>(c.v[static_cast<std::size_t>(at + 1)]),
          static_cast<T>(c.v[static_cast<std::size_t>(at + 2)])};
}

/// Spawned rays from the method's hit on `in` (inputs as the method saw them), computed in T.
template <class T>
std::array<io::Case, 8> spawned_cases(const io::Case& in, double t_hit, gen::Rng& rng, double epsilon, const Method& exact) {
  const Vec3<T> o = vec<T>(in, 0), d = vec<T>(in, 3), c = vec<T>(in, 6);
  const Vec3<T> p = in.kind == io::Kind::sphere ? reproject_to_sphere(o + static_cast<T>(t_hit) * d, c, static_cast<T>(in.v[9]))
                                                : reproject_to_plane(o + static_cast<T>(t_hit) * d, c, vec<T>(in, 9));
  const SurfacePoint<T> sp = in.kind == io::Kind::sphere ? surface_point_on_sphere(p, c, static_cast<T>(in.v[9]))
                                                         : surface_point_on_plane(p, c, vec<T>(in, 9));
  const Vec3<T> n_in = dot(d, sp.n) < T(0) ? sp.n : -sp.n;  // the side the primary ray came from
  const Vec3<T> reflect = d - (T(2) * dot(d, sp.n)) * sp.n;
  // Toward a light above the tangent plane on the incoming side: w.n_in = up > 0 up to rounding,
  // so w cannot legitimately meet the convex primitive or the plane again.
  const Vec3<double> j = random_unit(rng);
  const T up = static_cast<T>(rng.uniform(0.2, 3));
  Vec3<T> tangential{static_cast<T>(j.x), static_cast<T>(j.y), static_cast<T>(j.z)};
  tangential = tangential - dot(tangential, n_in) * n_in;
  const Vec3<T> to_light = up * n_in + tangential;
  auto as_case = [&](const Ray<T>& ray) {
    io::Case k = in;
    k.v[0] = ray.o.x, k.v[1] = ray.o.y, k.v[2] = ray.o.z;
    k.v[3] = ray.d.x, k.v[4] = ray.d.y, k.v[5] = ray.d.z;
    return k;
  };
  auto meets_own = [&](const Ray<T>& ray) { return self_hit(exact.classify(as_case(ray))); };
  std::array<io::Case, 8> out{};
  std::size_t i = 0;
  for (SpawnStrategy s : kStrategies)
    for (const Vec3<T>& w : {reflect, to_light}) {
      int steps = 0;
      out[i++] = as_case(s == SpawnStrategy::certified ? spawn_ray_certified(sp, w, meets_own, steps)
                                                       : spawn_ray(sp, w, s, static_cast<T>(epsilon)));
    }
  return out;
}

}  // namespace

std::string_view to_string(SpawnStrategy s) {
  switch (s) {
    case SpawnStrategy::none: return "none";
    case SpawnStrategy::fixed_epsilon: return "fixed-epsilon";
    case SpawnStrategy::error_bounded: return "error-bounded";
    case SpawnStrategy::certified: return "certified";
  }
  return "?";
}

std::vector<SpawnCount> count_self_intersections(io::Kind kind, std::span<const Method* const> methods,
                                                 const Method& exact, std::uint64_t trials, std::uint64_t seed,
                                                 int magnitude_log2, double epsilon) {
  if (kind != io::Kind::plane && kind != io::Kind::sphere && kind != io::Kind::disk)
    throw std::invalid_argument("spawn counts are for plane, sphere and disk");
  for (const Method* m : methods)
    if (!m->supports(kind)) throw std::invalid_argument("method '" + m->name + "' does not answer " + std::string(io::to_string(kind)));
  std::vector<SpawnCount> rows;
  for (const Method* m : methods)
    for (SpawnStrategy s : kStrategies) rows.push_back({kind, magnitude_log2, s, m});
  const double scale = std::ldexp(1.0, magnitude_log2);
  for (std::size_t mi = 0; mi < methods.size(); ++mi) {
    const Method& m = *methods[mi];
    // The same primitives and rays for every method (the stream depends on the seed only).
    gen::Rng rng(seed);
    for (std::uint64_t k = 0; k < trials; ++k) {
      const io::Case primary = make_case(kind, rng, scale);
      const io::Case in = m.precision == Precision::float32 ? io::round_to_float(primary) : primary;
      gen::Rng side_rng(seed ^ (0x9e3779b97f4a7c15ULL * (k + 1)));
      const io::CaseResult r = m.classify(in);
      SpawnCount* row = &rows[mi * kStrategies.size()];
      if (!primary_hit(r)) {
        for (std::size_t s = 0; s < kStrategies.size(); ++s) ++row[s].primary_misses;
        continue;
      }
      const auto spawned = m.precision == Precision::float32 ? spawned_cases<float>(in, *r.t, side_rng, epsilon, exact)
                                                             : spawned_cases<double>(in, *r.t, side_rng, epsilon, exact);
      for (std::size_t j = 0; j < spawned.size(); ++j) {
        SpawnCount& cnt = row[j / 2];
        ++cnt.spawned;
        if (self_hit(m.classify(spawned[j]))) ++cnt.self_hits;
        if (self_hit(exact.classify(spawned[j]))) ++cnt.exact_self_hits;
      }
    }
  }
  return rows;
}

namespace {

/// Shadow rays through a thin slab, computed in T: the top disk's hit point, the light below the
/// bottom disk; one spawned case per strategy (against the bottom disk).
template <class T>
std::array<io::Case, 4> slab_cases(const io::Case& top, const io::Case& bottom, double t_hit, Vec3<double> light,
                                   double epsilon, const Method& exact) {
  const Vec3<T> o = vec<T>(top, 0), d = vec<T>(top, 3), c = vec<T>(top, 6);
  const Vec3<T> p = reproject_to_plane(o + static_cast<T>(t_hit) * d, c, vec<T>(top, 9));
  const SurfacePoint<T> sp = surface_point_on_plane(p, c, vec<T>(top, 9));
  const Vec3<T> w = Vec3<T>{static_cast<T>(light.x), static_cast<T>(light.y), static_cast<T>(light.z)} - p;
  auto with_ray = [](const io::Case& prim, const Ray<T>& ray) {
    io::Case k = prim;
    k.v[0] = ray.o.x, k.v[1] = ray.o.y, k.v[2] = ray.o.z;
    k.v[3] = ray.d.x, k.v[4] = ray.d.y, k.v[5] = ray.d.z;
    return k;
  };
  auto meets_own = [&](const Ray<T>& ray) { return self_hit(exact.classify(with_ray(top, ray))); };
  std::array<io::Case, 4> out{};
  std::size_t i = 0;
  for (SpawnStrategy s : kStrategies) {
    int steps = 0;
    out[i++] = with_ray(bottom, s == SpawnStrategy::certified ? spawn_ray_certified(sp, w, meets_own, steps)
                                                              : spawn_ray(sp, w, s, static_cast<T>(epsilon)));
  }
  return out;
}

/// The bottom disk occludes the light: a contact at 0 < t <= 1 (w runs from the origin to the light).
bool blocks(const io::CaseResult& r) {
  return (r.contact == Contact::hit || r.contact == Contact::rim) && r.t && *r.t > 0 && *r.t <= 1;
}

}  // namespace

std::vector<SpawnCount> count_slab_leaks(std::span<const Method* const> methods, const Method& exact,
                                         std::uint64_t trials, std::uint64_t seed, int magnitude_log2, double gap,
                                         double epsilon) {
  for (const Method* m : methods)
    if (!m->supports(io::Kind::disk)) throw std::invalid_argument("method '" + m->name + "' does not answer disk");
  if (!(gap > 0 && std::isfinite(gap))) throw std::invalid_argument("the slab's gap must be finite and > 0");
  std::vector<SpawnCount> rows;
  for (const Method* m : methods)
    for (SpawnStrategy s : kStrategies) rows.push_back({io::Kind::disk, magnitude_log2, s, m});
  const double scale = std::ldexp(1.0, magnitude_log2);
  for (std::size_t mi = 0; mi < methods.size(); ++mi) {
    const Method& m = *methods[mi];
    gen::Rng rng(seed);
    for (std::uint64_t k = 0; k < trials; ++k) {
      const io::Case top = make_case(io::Kind::disk, rng, scale);
      const Vec3<double> n{top.v[9], top.v[10], top.v[11]}, c{top.v[6], top.v[7], top.v[8]};
      io::Case bottom = top;
      const Vec3<double> cb = c - gap * n;
      bottom.v[6] = cb.x, bottom.v[7] = cb.y, bottom.v[8] = cb.z;
      const Vec3<double> light = in_disk(rng, cb - rng.uniform(0.5, 3) * n, n, 0.3 * top.v[12]);
      const io::Case in_top = m.precision == Precision::float32 ? io::round_to_float(top) : top;
      const io::Case in_bottom = m.precision == Precision::float32 ? io::round_to_float(bottom) : bottom;
      SpawnCount* row = &rows[mi * kStrategies.size()];
      const io::CaseResult r = m.classify(in_top);
      if (!primary_hit(r)) {
        for (std::size_t s = 0; s < kStrategies.size(); ++s) ++row[s].primary_misses;
        continue;
      }
      const auto cases = m.precision == Precision::float32 ? slab_cases<float>(in_top, in_bottom, *r.t, light, epsilon, exact)
                                                           : slab_cases<double>(in_top, in_bottom, *r.t, light, epsilon, exact);
      for (std::size_t j = 0; j < cases.size(); ++j) {
        ++row[j].spawned;
        if (!blocks(m.classify(cases[j]))) ++row[j].self_hits;
        if (!blocks(exact.classify(cases[j]))) ++row[j].exact_self_hits;
      }
    }
  }
  return rows;
}

}  // namespace rayproof::light
