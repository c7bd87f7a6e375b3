/// rayproof::certified::intersect (rayproof/certified/intersect.h): the header-only filters, then the
/// certified fallback (exact/fallback.h: exact, GMP, no CGAL) for what they leave undecided.
#include "rayproof/certified/intersect.h"

#include "exact/fallback.h"

namespace rayproof::certified {

namespace {

// Per thread: no contention between threads, and a caller can attribute fallbacks to its own calls.
thread_local std::uint64_t g_fallbacks = 0;

template <class Prim>
auto complete(const Ray<double>& ray, const Prim& prim) {
  if (auto h = try_intersect(ray, prim)) return *h;
  ++g_fallbacks;
  return fallback::intersect(ray, prim);
}

}  // namespace

Hit<double> intersect(const Ray<double>& ray, const Plane<double>& p) { return complete(ray, p); }
Hit<double> intersect(const Ray<double>& ray, const Sphere<double>& s) { return complete(ray, s); }
Hit<double> intersect(const Ray<double>& ray, const Ellipsoid<double>& e) { return complete(ray, e); }
Hit<double> intersect(const Ray<double>& ray, const Box<double>& b) { return complete(ray, b); }
Hit<double> intersect(const Ray<double>& ray, const Disk<double>& dk) { return complete(ray, dk); }
TriangleHit<double> intersect(const Ray<double>& ray, const Triangle<double>& tri) { return complete(ray, tri); }

std::uint64_t fallback_count() { return g_fallbacks; }

}  // namespace rayproof::certified
