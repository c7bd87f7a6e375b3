#include "rayproof/triangle.h"

#include <gtest/gtest.h>

#include <random>

using namespace rayproof;

template <class P> class TriangleTest : public ::testing::Test {};
template <class T, TriangleMethod M> struct Param {
  using Scalar = T;
  static constexpr TriangleMethod method = M;
};
using Params = ::testing::Types<Param<float, TriangleMethod::moller_trumbore>, Param<double, TriangleMethod::moller_trumbore>,
                                Param<float, TriangleMethod::cramer>, Param<double, TriangleMethod::cramer>>;
TYPED_TEST_SUITE(TriangleTest, Params);

template <class P>
TriangleHit<typename P::Scalar> run(std::initializer_list<double> v) {
  using T = typename P::Scalar;
  std::vector<T> a;
  for (double x : v) a.push_back(T(x));
  const Ray<T> ray{{a[0], a[1], a[2]}, {a[3], a[4], a[5]}};
  const Triangle<T> tri{{a[6], a[7], a[8]}, {a[9], a[10], a[11]}, {a[12], a[13], a[14]}};
  return intersect(ray, tri, P::method);
}

TYPED_TEST(TriangleTest, WorkedExamples) {
  using T = typename TypeParam::Scalar;
  auto h = run<TypeParam>({0, 0, 0, 1, 1, 1, 2, 4, 2, 5, -7, -1, 0, -9, 4});
  EXPECT_EQ(h.contact, Contact::interior);
  EXPECT_NEAR(h.t, T(2), T(4) * std::numeric_limits<T>::epsilon() * 2);
  h = run<TypeParam>({0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 7, -1, 0, 9, -4});
  EXPECT_EQ(h.contact, Contact::vertex);
  EXPECT_EQ(h.t, T(2));
  h = run<TypeParam>({0, 0, 0, 1, 1, 1, -1, -1, -1, 3, 7, -1, 0, 9, -4});
  EXPECT_EQ(h.contact, Contact::behind);
  EXPECT_EQ(h.t, T(-1));
  h = run<TypeParam>({0, 0, 1, 1, 1, 0, 3, 3, 1, 7, 7, 1, 0, -9, -4});
  EXPECT_EQ(h.contact, Contact::coplanar);
  EXPECT_EQ(h.t, T(3));
  EXPECT_EQ(h.t2, T(7));
  h = run<TypeParam>({0, 0, 0, 0, 0, 1, -1, -1, 5, 1, -1, 5, 0, 1, 5});
  EXPECT_EQ(h.contact, Contact::interior);
  EXPECT_EQ(h.t, T(5));
  h = run<TypeParam>({0, 0, 0, 0, 0, 1, -1, 0, 5, 1, 0, 5, 0, 1, 5});
  EXPECT_EQ(h.contact, Contact::edge);
  EXPECT_EQ(h.t, T(5));
  EXPECT_EQ(run<TypeParam>({0, 0, 0, 1, 0, 0, 0, 0, 5, 1, 0, 5, 2, 0, 5}).contact, Contact::degenerate);
}

TYPED_TEST(TriangleTest, ParallelCoplanarMissInvalid) {
  EXPECT_EQ(run<TypeParam>({0, 0, 0, 1, 0, 0, 0, 0, 5, 1, 0, 5, 0, 1, 5}).contact, Contact::parallel);
  const auto away = run<TypeParam>({10, 10, 5, 1, 0, 0, 0, 0, 5, 1, 0, 5, 0, 1, 5});
  EXPECT_EQ(away.contact, Contact::coplanar);
  EXPECT_TRUE(std::isnan(away.t));
  EXPECT_EQ(run<TypeParam>({3, 3, 0, 0, 0, 1, 0, 0, 5, 1, 0, 5, 0, 1, 5}).contact, Contact::miss);
  EXPECT_EQ(run<TypeParam>({0, 0, 0, 0, 0, 0, 0, 0, 5, 1, 0, 5, 0, 1, 5}).contact, Contact::invalid);
  EXPECT_EQ(run<TypeParam>({0, 0, 0, 0, 0, 1, 0, 0, 5, 1, 0, 5, 0, 1, NAN}).contact, Contact::invalid);
}

// Points built on the triangle from barycentrics are hit at the right t and barycentrics.
TYPED_TEST(TriangleTest, PointsBuiltOnTheTriangleAreHit) {
  using T = typename TypeParam::Scalar;
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> u(-1, 1), w(0.05, 0.9);
  const double tol = std::is_same_v<T, float> ? 2e-3 : 1e-9;
  for (int i = 0; i < 1000; ++i) {
    const Vec3<double> p0{u(rng), u(rng), u(rng)}, p1{u(rng), u(rng), u(rng)}, p2{u(rng), u(rng), u(rng)};
    const Vec3<double> n = cross(p1 - p0, p2 - p0);
    if (length(n) < 0.2) continue;  // well-shaped triangles only: tolerance stays meaningful
    double b1 = w(rng), b2 = w(rng);
    if (b1 + b2 > 0.95) b1 *= 0.5, b2 *= 0.5;
    const Vec3<double> q = (1 - b1 - b2) * p0 + b1 * p1 + b2 * p2;
    const Vec3<double> d = normalize(n) * (u(rng) > 0 ? 1.0 : -1.0) + 0.3 * Vec3<double>{u(rng), u(rng), u(rng)};
    const double t = 1 + 3 * w(rng);
    const Vec3<double> o = q - t * d;
    const auto h = intersect(Ray<T>{o.cast<T>(), d.cast<T>()},
                             Triangle<T>{p0.cast<T>(), p1.cast<T>(), p2.cast<T>()}, TypeParam::method);
    ASSERT_EQ(h.contact, Contact::interior) << i;
    EXPECT_NEAR(h.t, t, tol * 10);
    EXPECT_NEAR(h.b1, b1, tol);
    EXPECT_NEAR(h.b2, b2, tol);
  }
}
