#pragma once
/// Builds kernel inputs (ray and primitive in scalar type T) from a case's fields (docs/cases.md order).
#include "io/case_file.h"
#include "rayproof/box.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/plane.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"

namespace rayproof {

template <class T>
Vec3<T> vec_at(const io::Case& c, int i) {
  return {static_cast<T>(c.v[i]), static_cast<T>(c.v[i + 1]), static_cast<T>(c.v[i + 2])};
}
template <class T> Ray<T> ray_of(const io::Case& c) { return {vec_at<T>(c, 0), vec_at<T>(c, 3)}; }
template <class T> Plane<T> plane_of(const io::Case& c) { return {vec_at<T>(c, 6), vec_at<T>(c, 9)}; }
template <class T> Sphere<T> sphere_of(const io::Case& c) { return {vec_at<T>(c, 6), static_cast<T>(c.v[9])}; }
template <class T> Ellipsoid<T> ellipsoid_of(const io::Case& c) { return {vec_at<T>(c, 6), vec_at<T>(c, 9)}; }
template <class T> Triangle<T> triangle_of(const io::Case& c) { return {vec_at<T>(c, 6), vec_at<T>(c, 9), vec_at<T>(c, 12)}; }
template <class T> Box<T> box_of(const io::Case& c) { return {vec_at<T>(c, 6), vec_at<T>(c, 9)}; }
/// The two triangles of a `tritri` case: a = (p0, p1, p2), b = (q0, q1, q2).
template <class T> Triangle<T> first_triangle_of(const io::Case& c) { return {vec_at<T>(c, 0), vec_at<T>(c, 3), vec_at<T>(c, 6)}; }
template <class T> Triangle<T> second_triangle_of(const io::Case& c) { return {vec_at<T>(c, 9), vec_at<T>(c, 12), vec_at<T>(c, 15)}; }
template <class T> Disk<T> disk_of(const io::Case& c) { return {vec_at<T>(c, 6), vec_at<T>(c, 9), static_cast<T>(c.v[12])}; }

}  // namespace rayproof
