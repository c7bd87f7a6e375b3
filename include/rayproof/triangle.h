#pragma once
/// One front door for the ray/triangle methods: intersect(ray, tri, TriangleMethod).
#include "rayproof/triangle_cramer.h"
#include "rayproof/triangle_moller_trumbore.h"

namespace rayproof {

enum class TriangleMethod { moller_trumbore, cramer };

template <class T>
[[nodiscard]] TriangleHit<T> intersect(const Ray<T>& ray, const Triangle<T>& tri,
                                       TriangleMethod m = TriangleMethod::moller_trumbore) {
  switch (m) {
    case TriangleMethod::cramer: return intersect_cramer(ray, tri);
    case TriangleMethod::moller_trumbore: break;
  }
  return intersect_moller_trumbore(ray, tri);
}

}  // namespace rayproof
