#pragma once
/// The ground truth per kind (internal to rayproof_verify; CGAL exact number types). Each takes
/// inputs that rayproof::exact::intersect (exact_api.cpp) has already screened: every field finite, d != 0, no negative size, no inverted box, no zero
/// normal / radius / semi-axis. Only the triangle's degeneracy (collinear vertices) needs exact
/// arithmetic and is decided by exact_triangle itself. Fields a class does not carry are NaN.
#include "rayproof/box.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/hit.h"
#include "rayproof/plane.h"
#include "rayproof/ray.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"

namespace rayproof::verify {

[[nodiscard]] Hit<double> exact_plane(const Ray<double>& ray, const Plane<double>& pl);
[[nodiscard]] Hit<double> exact_disk(const Ray<double>& ray, const Disk<double>& dk);
[[nodiscard]] Hit<double> exact_sphere(const Ray<double>& ray, const Sphere<double>& s);
[[nodiscard]] Hit<double> exact_ellipsoid(const Ray<double>& ray, const Ellipsoid<double>& e);
[[nodiscard]] TriangleHit<double> exact_triangle(const Ray<double>& ray, const Triangle<double>& tri);
[[nodiscard]] Hit<double> exact_box(const Ray<double>& ray, const Box<double>& box);

}  // namespace rayproof::verify
