#pragma once
/// Camera ray generation, raster -> NDC -> screen -> camera -> world, for perspective and
/// orthographic cameras. Pixel (i, j) has i to the right, j downwards, and its centre at raster
/// (i + 0.5, j + 0.5). NDC is [0,1]^2 (y down), screen is [-1,1]^2 with y flipped (up).
///
/// The worked problems write the camera-space step as (2 PixelScreen - 1) aspect tan(alpha/2),
/// which applies the [-1,1] remap twice when PixelScreen is already in [-1,1]; here the remap is
/// done once, in screen_from_raster, and camera space scales screen coordinates only.
#include <cmath>

#include "rayproof/ray.h"
#include "rayproof/transform.h"

namespace rayproof {

template <class T>
struct ScreenPoint {
  T x, y;  ///< in [-1, 1], y up
};

/// Raster position (pixel centre for i + 0.5, j + 0.5) of a width x height image to screen space.
template <class T>
[[nodiscard]] constexpr ScreenPoint<T> screen_from_raster(T raster_x, T raster_y, int width, int height) {
  const T ndc_x = raster_x / T(width);
  const T ndc_y = raster_y / T(height);
  return {T(2) * ndc_x - T(1), T(1) - T(2) * ndc_y};
}

/// Pinhole camera with vertical field of view `fov_y` (radians) at the origin of camera space,
/// looking along -z; world_from_camera places it in the world.
template <class T>
struct PerspectiveCamera {
  int width = 1, height = 1;
  T fov_y{};  ///< vertical field of view, radians, in (0, pi)
  Transform<T> world_from_camera;

  [[nodiscard]] T aspect() const { return T(width) / T(height); }

  /// Camera-space direction through a screen point: (x aspect tan(fov/2), y tan(fov/2), -1).
  [[nodiscard]] Vec3<T> camera_direction(ScreenPoint<T> s) const {
    const T h = std::tan(fov_y / T(2));
    return {s.x * aspect() * h, s.y * h, T(-1)};
  }

  /// Primary ray through the centre of pixel (i, j), in world space (direction not normalized).
  [[nodiscard]] Ray<T> generate(int i, int j) const {
    const ScreenPoint<T> s = screen_from_raster(T(i) + T(0.5), T(j) + T(0.5), width, height);
    return {world_from_camera.point({0, 0, 0}), world_from_camera.vector(camera_direction(s))};
  }

  [[nodiscard]] static PerspectiveCamera look_at(int width, int height, T fov_y, Vec3<T> eye, Vec3<T> target,
                                                 Vec3<T> up) {
    const Frame<T> f = rayproof::look_at(eye, target, up);
    return {width, height, fov_y, Transform<T>::from_frame(f.u, f.v, f.w, f.eye)};
  }
};

/// Orthographic camera (Shirley & Marschner): frame u, v, w at eye e, image rectangle
/// [l, r] x [b, t] in the u-v plane; every ray starts on that plane and points along -w.
template <class T>
struct OrthographicCamera {
  int width = 1, height = 1;
  Frame<T> frame;
  T l{-1}, r{1}, b{-1}, t{1};

  [[nodiscard]] Ray<T> generate(int i, int j) const {
    const ScreenPoint<T> s = screen_from_raster(T(i) + T(0.5), T(j) + T(0.5), width, height);
    const T su = l + (r - l) * (s.x + T(1)) / T(2);
    const T sv = b + (t - b) * (s.y + T(1)) / T(2);
    return {frame.eye + su * frame.u + sv * frame.v, -frame.w};
  }
};

}  // namespace rayproof
