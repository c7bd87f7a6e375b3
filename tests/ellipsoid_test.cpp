#include "rayproof/ellipsoid.h"

#include <gtest/gtest.h>

#include "rayproof/float_util.h"

using namespace rayproof;

TEST(Ellipsoid, WorkedExampleDouble) {
  // Centre (2,2,0), semi-axes (2,1,2), ray from the origin along (1,1,0): t = 2 -+ sqrt(4/5).
  const auto h = intersect(Ray<double>{{0, 0, 0}, {1, 1, 0}}, Ellipsoid<double>{{2, 2, 0}, {2, 1, 2}});
  ASSERT_EQ(h.contact, Contact::hit);
  const long double r = std::sqrt(4.0L / 5.0L);
  EXPECT_LE(ulp_distance(h.t, double(2.0L - r)), 4u);
  EXPECT_LE(ulp_distance(h.t2, double(2.0L + r)), 4u);
}

TEST(Ellipsoid, WorkedExampleFloat) {
  const auto h = intersect(Ray<float>{{0, 0, 0}, {1, 1, 0}}, Ellipsoid<float>{{2, 2, 0}, {2, 1, 2}});
  ASSERT_EQ(h.contact, Contact::hit);
  EXPECT_LE(ulp_distance(h.t, float(2.0 - std::sqrt(0.8))), 4u);
  EXPECT_LE(ulp_distance(h.t2, float(2.0 + std::sqrt(0.8))), 4u);
}

TEST(Ellipsoid, SphereCaseAgreesWithScaling) {
  // Semi-axes (1, 4, 1): the ray along y through the centre crosses at y = -+4.
  const auto h = intersect(Ray<double>{{0, -10, 0}, {0, 2, 0}}, Ellipsoid<double>{{0, 0, 0}, {1, 4, 1}});
  ASSERT_EQ(h.contact, Contact::hit);
  EXPECT_DOUBLE_EQ(h.t, 3.0);
  EXPECT_DOUBLE_EQ(h.t2, 7.0);
  EXPECT_EQ(intersect(Ray<double>{{1, -10, 0}, {0, 1, 0}}, Ellipsoid<double>{{0, 0, 0}, {1, 4, 1}}).contact,
            Contact::tangent);
}

TEST(Ellipsoid, InvalidAndDegenerate) {
  const Ray<double> ray{{0, 0, 0}, {1, 0, 0}};
  EXPECT_EQ(intersect(ray, Ellipsoid<double>{{5, 0, 0}, {1, -1, 1}}).contact, Contact::invalid);
  EXPECT_EQ(intersect(ray, Ellipsoid<double>{{5, 0, 0}, {1, 0, 1}}).contact, Contact::degenerate);
}
