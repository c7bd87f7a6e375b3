#pragma once
/// Spawning secondary rays (shadow, reflection) from a computed hit point so that they do not hit
/// the surface they leave ("shadow acne"). Four origin strategies:
/// - none: the computed hit point itself;
/// - fixed_epsilon: the hit point pushed a fixed distance along the normal, toward the side the
///   ray leaves to (the common renderer habit; the distance means nothing at large magnitudes);
/// - error_bounded: pbrt-v4's OffsetRayOrigin (M. Pharr, W. Jakob, G. Humphreys, "Physically Based
///   Rendering", 4th ed., 2023, §6.8.6): a conservative bound on the hit point's distance from the
///   surface, the origin pushed along the normal past it, each coordinate then rounded one ulp
///   further away from the hit point.
/// - certified: the hit point moved one ulp at a time along the normal's signs (toward the side
///   the ray leaves to) until an exact classifier of the caller's says the spawned ray no longer
///   meets the primitive it leaves: the smallest such step on this lattice walk, so as little
///   light as possible leaks through thin geometry (spawn_ray_certified).
/// The error bound here is a posteriori (the residual of the surface equation at the computed
/// point, with its own rounding bound), so it holds however the point was computed: plane and disk
/// (point c, normal N): |(p - c).N| / |N|; sphere (centre c, radius r): ||p - c|^2 - r^2| / r.
#include <cmath>

#include "rayproof/float_util.h"
#include "rayproof/ray.h"
#include "rayproof/vec3.h"

namespace rayproof {

enum class SpawnStrategy : unsigned char { none, fixed_epsilon, error_bounded, certified };

/// A computed surface point: where, how far at most from the surface (along the unit normal), and
/// the unit normal (either orientation).
template <class T>
struct SurfacePoint {
  Vec3<T> p;
  T distance_bound{};  ///< the surface is within this distance of p, along n
  Vec3<T> n;           ///< unit length, up to rounding
};

/// Hit point refinement (as pbrt-v4 does for its quadrics): the computed point o + t d carries the
/// error of t times |d| and of the sum, often far more than an ulp of p; projecting it back onto
/// the surface leaves only the rounding of the projection. Plane or disk through c with normal N:
[[nodiscard]] inline auto reproject_to_plane(auto p, auto c, auto normal) {
  return p - (dot(p - c, normal) / dot(normal, normal)) * normal;
}
/// Sphere with centre c and radius r: c + r (p - c) / |p - c|.
[[nodiscard]] inline auto reproject_to_sphere(auto p, auto c, auto r) {
  const auto q = p - c;
  return c + (r / length(q)) * q;
}

/// Plane or disk through c with normal N (any non-zero length).
template <class T>
[[nodiscard]] SurfacePoint<T> surface_point_on_plane(Vec3<T> p, Vec3<T> c, Vec3<T> normal) {
  const Vec3<T> q = p - c;
  const T res = dot(q, normal);
  // fl(q) - (p - c) is within u |q_i| per component; the dot product adds gamma(3) of sum |q_i N_i|.
  const T abs_dot = std::fabs(q.x * normal.x) + std::fabs(q.y * normal.y) + std::fabs(q.z * normal.z);
  const T len = length(normal);
  const T bound = (std::fabs(res) + gamma<T>(4) * abs_dot) / len * (1 + gamma<T>(4));
  return {p, bound, normal / len};
}

/// Sphere with centre c and radius r > 0.
template <class T>
[[nodiscard]] SurfacePoint<T> surface_point_on_sphere(Vec3<T> p, Vec3<T> c, T r) {
  const Vec3<T> q = p - c;
  const T q2 = dot(q, q);
  const T res = q2 - r * r;
  // ||p - c| - r| = |q2 - r^2| / (|q| + r) <= (|res| + rounding) / r; rounding of q (u |q_i|), of the
  // dot product and r^2 and the subtraction: gamma(5) (q2 + r^2).
  const T bound = (std::fabs(res) + gamma<T>(5) * (q2 + r * r)) / r * (1 + gamma<T>(3));
  return {p, bound, q / std::sqrt(q2)};
}

/// pbrt-v4's offset: p + d n on the side of w, d the bound, rounded away from p.
template <class T>
[[nodiscard]] Vec3<T> offset_ray_origin(const SurfacePoint<T>& sp, Vec3<T> w) {
  const Vec3<T> side = dot(w, sp.n) < T(0) ? -sp.n : sp.n;
  Vec3<T> po = sp.p + sp.distance_bound * side;
  // Rounded one ulp further along the normal's signs (also when the bound is 0).
  for (std::size_t i = 0; i < 3; ++i) {
    if (side[i] > T(0)) po[i] = next_up(po[i]);
    else if (side[i] < T(0)) po[i] = next_down(po[i]);
  }
  return po;
}

/// A ray leaving the surface point in direction w by the chosen strategy.
template <class T>
[[nodiscard]] Ray<T> spawn_ray(const SurfacePoint<T>& sp, Vec3<T> w, SpawnStrategy strategy, T epsilon) {
  switch (strategy) {
    case SpawnStrategy::none: return {sp.p, w};
    case SpawnStrategy::fixed_epsilon: return {sp.p + (dot(w, sp.n) < T(0) ? -epsilon : epsilon) * sp.n, w};
    case SpawnStrategy::error_bounded: return {offset_ray_origin(sp, w), w};
    case SpawnStrategy::certified: break;  // needs a classifier: spawn_ray_certified
  }
  return {sp.p, w};
}

/// The certified strategy. `meets_own(ray)` must say exactly whether the ray meets the primitive
/// it leaves at t > 0 (an exact or certified kernel). At most `max_steps` ulp steps; if the
/// classifier still objects, the error-bounded origin is returned (and `steps` is max_steps + 1).
template <class T, class MeetsOwn>
[[nodiscard]] Ray<T> spawn_ray_certified(const SurfacePoint<T>& sp, Vec3<T> w, MeetsOwn&& meets_own, int& steps,
                                         int max_steps = 64) {
  const Vec3<T> side = dot(w, sp.n) < T(0) ? -sp.n : sp.n;
  Ray<T> ray{sp.p, w};
  for (steps = 0; steps <= max_steps; ++steps) {
    if (!meets_own(ray)) return ray;
    for (std::size_t i = 0; i < 3; ++i) {
      if (side[i] > T(0)) ray.o[i] = next_up(ray.o[i]);
      else if (side[i] < T(0)) ray.o[i] = next_down(ray.o[i]);
    }
  }
  steps = max_steps + 1;
  return {offset_ray_origin(sp, w), w};
}

}  // namespace rayproof
