#include "rayproof/triangle_watertight.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace rayproof;

template <class T, class A>
TriangleHit<T> wt(std::initializer_list<double> v) {
  std::vector<T> a;
  for (double x : v) a.push_back(T(x));
  const Ray<T> ray{{a[0], a[1], a[2]}, {a[3], a[4], a[5]}};
  const Triangle<T> tri{{a[6], a[7], a[8]}, {a[9], a[10], a[11]}, {a[12], a[13], a[14]}};
  return intersect_watertight<T, A>(ray, tri);
}

template <class P> class WatertightTest : public ::testing::Test {};
template <class T, class A> struct Param {
  using Scalar = T;
  using Arith = A;
};
using Params = ::testing::Types<Param<float, float>, Param<float, double>, Param<double, double>>;
TYPED_TEST_SUITE(WatertightTest, Params);

TYPED_TEST(WatertightTest, WorkedExamples) {
  using T = typename TypeParam::Scalar;
  using A = typename TypeParam::Arith;
  auto w = [](std::initializer_list<double> v) { return wt<T, A>(v); };
  auto h = w({0, 0, 0, 1, 1, 1, 2, 4, 2, 5, -7, -1, 0, -9, 4});
  EXPECT_EQ(h.contact, Contact::interior);
  EXPECT_NEAR(h.t, T(2), T(8) * std::numeric_limits<T>::epsilon());
  h = w({0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 7, -1, 0, 9, -4});  // CASES.md: vertex 2
  EXPECT_EQ(h.contact, Contact::vertex);
  EXPECT_EQ(h.t, T(2));
  h = w({0, 0, 0, 1, 1, 1, -1, -1, -1, 3, 7, -1, 0, 9, -4});
  EXPECT_EQ(h.contact, Contact::behind);
  EXPECT_EQ(h.t, T(-1));
  h = w({0, 0, 1, 1, 1, 0, 3, 3, 1, 7, 7, 1, 0, -9, -4});  // CASES.md: coplanar 3 7
  EXPECT_EQ(h.contact, Contact::coplanar);
  EXPECT_EQ(h.t, T(3));
  EXPECT_EQ(h.t2, T(7));
  h = w({0, 0, 0, 0, 0, -1, -1, 0, -5, 1, 0, -5, 0, 1, -5});  // edge p0p1: b2 = 0
  EXPECT_EQ(h.contact, Contact::edge);
  EXPECT_EQ(h.t, T(5));
  EXPECT_EQ(h.b2, T(0));
  EXPECT_EQ(h.b1, T(0.5));
  EXPECT_EQ(w({0, 0, 0, 1, 0, 0, 0, 0, 5, 1, 0, 5, 2, 0, 5}).contact, Contact::degenerate);
  EXPECT_EQ(w({0, 0, 0, 1, 0, 0, 0, 0, 5, 1, 0, 5, 0, 1, 5}).contact, Contact::parallel);
  EXPECT_EQ(w({0, 0, 0, 0, 0, 1, 2, 2, 5, 3, 2, 5, 2, 3, 5}).contact, Contact::miss);
  EXPECT_EQ(w({0, 0, NAN, 0, 0, 1, 2, 2, 5, 3, 2, 5, 2, 3, 5}).contact, Contact::invalid);
  EXPECT_EQ(w({0, 0, 0, 0, 0, 0, 2, 2, 5, 3, 2, 5, 2, 3, 5}).contact, Contact::invalid);
}

/// Random fans of triangles around a shared vertex, and pairs sharing an edge; rays through the
/// shared vertex / a point of the shared edge (rounded to T) must hit at least one of them.
TYPED_TEST(WatertightTest, NeverLeaksThroughSharedEdgesAndVertices) {
  using T = typename TypeParam::Scalar;
  using A = typename TypeParam::Arith;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto rv = [&] { return Vec3<T>{T(u(rng)), T(u(rng)), T(u(rng))}; };
  int rays = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    // A fan of 6 triangles around c, ring vertices on a perturbed circle.
    const Vec3<T> c = rv();
    Vec3<T> ring[6];
    for (int i = 0; i < 6; ++i) {
      const double ang = 2 * 3.141592653589793 * i / 6;
      ring[i] = c + Vec3<T>{T(std::cos(ang) + 0.3 * u(rng)), T(std::sin(ang) + 0.3 * u(rng)), T(0.5 * u(rng))};
    }
    const Vec3<T> o = c + Vec3<T>{T(0.2 * u(rng)), T(0.2 * u(rng)), T(3 + u(rng))};
    auto hits = [&](const Ray<T>& ray) {
      const WatertightRay<T, A> wr(ray);
      for (int i = 0; i < 6; ++i)
        if (is_hit(intersect_watertight(wr, Triangle<T>{c, ring[i], ring[(i + 1) % 6]}).contact)) return true;
      return false;
    };
    // Through the shared vertex, and through a point of each shared edge.
    EXPECT_TRUE(hits(Ray<T>{o, c - o})) << trial;
    for (int i = 0; i < 6; ++i) {
      const T s = T(0.5 * (u(rng) + 1));
      const Vec3<T> on = c + s * (ring[i] - c);
      EXPECT_TRUE(hits(Ray<T>{o, on - o})) << trial << " edge " << i;
      EXPECT_TRUE(hits(Ray<T>{o, normalize(on - o)})) << trial << " edge " << i << " normalized";
      ++rays;
    }
  }
  EXPECT_EQ(rays, 12000);
}
