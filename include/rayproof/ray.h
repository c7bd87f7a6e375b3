#pragma once
/// A ray r(t) = o + t d, t >= 0. d need not be unit length.
#include "rayproof/vec3.h"

namespace rayproof {

template <class T>
struct Ray {
  Vec3<T> o;  ///< origin (a point)
  Vec3<T> d;  ///< direction (a vector, any non-zero length)

  [[nodiscard]] constexpr Vec3<T> at(T t) const { return o + t * d; }

  /// A ray is invalid when a component is NaN or infinite or d = (0,0,0) (docs/cases.md).
  [[nodiscard]] bool valid() const { return all_finite(o) && all_finite(d) && !is_zero(d); }
};

}  // namespace rayproof
