#include "rayproof/sphere.h"

#include <gtest/gtest.h>

#include <random>

using namespace rayproof;

template <class T> class SphereTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(SphereTest, Scalars);

TYPED_TEST(SphereTest, WorkedExamples) {
  using T = TypeParam;
  const Sphere<T> s{{5, 0, 0}, 1};
  const auto hit = intersect(Ray<T>{{0, 0, 0}, {1, 0, 0}}, s);
  EXPECT_EQ(hit.contact, Contact::hit);
  EXPECT_EQ(hit.t, T(4));
  EXPECT_EQ(hit.t2, T(6));
  const auto tan = intersect(Ray<T>{{0, 1, 0}, {1, 0, 0}}, s);
  EXPECT_EQ(tan.contact, Contact::tangent);
  EXPECT_EQ(tan.t, T(5));
  const auto in = intersect(Ray<T>{{5, 0, 0}, {1, 0, 0}}, s);
  EXPECT_EQ(in.contact, Contact::inside);
  EXPECT_EQ(in.t, T(-1));
  EXPECT_EQ(in.t2, T(1));
  EXPECT_EQ(intersect(Ray<T>{{0, 0, 0}, {-1, 0, 0}}, s).contact, Contact::behind);
  EXPECT_EQ(intersect(Ray<T>{{0, 2, 0}, {1, 0, 0}}, s).contact, Contact::miss);
}

TYPED_TEST(SphereTest, RaysFromInsideAreInside) {
  using T = TypeParam;
  std::mt19937 rng(42);
  std::uniform_real_distribution<T> u(-1, 1);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3<T> c{u(rng) * 10, u(rng) * 10, u(rng) * 10};
    const T r = T(1) + (u(rng) + T(1)) * 4;
    Vec3<T> off{u(rng), u(rng), u(rng)};
    if (length_squared(off) >= T(0.9)) continue;  // strictly inside, away from the surface
    const Ray<T> ray{c + r * off, {u(rng), u(rng), u(rng) + T(2)}};
    const auto h = intersect(ray, Sphere<T>{c, r});
    EXPECT_EQ(h.contact, Contact::inside) << i;
    EXPECT_LT(h.t, T(0));
    EXPECT_GT(h.t2, T(0));
    ++checked;
  }
  EXPECT_GT(checked, 500);
}

TYPED_TEST(SphereTest, InvalidAndDegenerate) {
  using T = TypeParam;
  EXPECT_EQ(intersect(Ray<T>{{0, 0, 0}, {1, 0, 0}}, Sphere<T>{{5, 0, 0}, -1}).contact, Contact::invalid);
  EXPECT_EQ(intersect(Ray<T>{{0, 0, 0}, {1, 0, 0}}, Sphere<T>{{5, 0, 0}, 0}).contact, Contact::degenerate);
  EXPECT_EQ(intersect(Ray<T>{{0, 0, 0}, {0, 0, 0}}, Sphere<T>{{5, 0, 0}, 1}).contact, Contact::invalid);
  const T inf = std::numeric_limits<T>::infinity();
  EXPECT_EQ(intersect(Ray<T>{{0, 0, 0}, {1, 0, 0}}, Sphere<T>{{inf, 0, 0}, 1}).contact, Contact::invalid);
}
