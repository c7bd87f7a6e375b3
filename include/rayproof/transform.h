#pragma once
/// Affine 4x4 transforms, named destination_from_source (world_from_camera maps camera space to
/// world space). Row-major; points get the translation, vectors do not.
#include <array>

#include "rayproof/vec3.h"

namespace rayproof {

template <class T>
struct Transform {
  std::array<std::array<T, 4>, 4> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}};

  [[nodiscard]] constexpr Vec3<T> point(Vec3<T> p) const {
    const T x = m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3];
    const T y = m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3];
    const T z = m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3];
    const T w = m[3][0] * p.x + m[3][1] * p.y + m[3][2] * p.z + m[3][3];
    return w == T(1) ? Vec3<T>{x, y, z} : Vec3<T>{x / w, y / w, z / w};
  }
  [[nodiscard]] constexpr Vec3<T> vector(Vec3<T> v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }

  /// The transform whose columns are the basis u, v, w and the origin e: maps (a, b, c) in that frame
  /// to e + a u + b v + c w.
  [[nodiscard]] static constexpr Transform from_frame(Vec3<T> u, Vec3<T> v, Vec3<T> w, Vec3<T> e) {
    Transform t;
    t.m = {{{u.x, v.x, w.x, e.x}, {u.y, v.y, w.y, e.y}, {u.z, v.z, w.z, e.z}, {0, 0, 0, 1}}};
    return t;
  }
};

/// Orthonormal camera frame looking from `eye` at `target`: w points backwards (the camera looks
/// along -w), u to the right, v up (Shirley & Marschner's convention).
template <class T>
struct Frame {
  Vec3<T> u, v, w, eye;
};

template <class T>
[[nodiscard]] Frame<T> look_at(Vec3<T> eye, Vec3<T> target, Vec3<T> up) {
  const Vec3<T> w = normalize(eye - target);
  const Vec3<T> u = normalize(cross(up, w));
  return {u, cross(w, u), w, eye};
}

}  // namespace rayproof
