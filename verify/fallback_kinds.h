#pragma once
/// The certified fallback's exact kernels per kind (internal to the certified library; its entry
/// is fallback::intersect, verify/fallback.h). Each takes inputs that fallback::intersect has
/// screened: every field finite, d != 0, no negative size, no inverted box, no zero normal / radius / semi-axis. Only the
/// triangle's degeneracy (collinear vertices) needs exact arithmetic and is decided by
/// triangle_kernel itself. Fields a class does not carry are NaN (rayproof/hit.h).
#include "rayproof/box.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/hit.h"
#include "rayproof/plane.h"
#include "rayproof/ray.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"

namespace rayproof::certified::fallback {

[[nodiscard]] Hit<double> plane_kernel(const Ray<double>& ray, const Plane<double>& pl);
[[nodiscard]] Hit<double> disk_kernel(const Ray<double>& ray, const Disk<double>& dk);
[[nodiscard]] Hit<double> sphere_kernel(const Ray<double>& ray, const Sphere<double>& s);
[[nodiscard]] Hit<double> ellipsoid_kernel(const Ray<double>& ray, const Ellipsoid<double>& e);
[[nodiscard]] TriangleHit<double> triangle_kernel(const Ray<double>& ray, const Triangle<double>& tri);
[[nodiscard]] Hit<double> box_kernel(const Ray<double>& ray, const Box<double>& box);

}  // namespace rayproof::certified::fallback
