#include "rayproof/camera.h"

#include <gtest/gtest.h>

#include <numbers>

using namespace rayproof;

TEST(Camera, ScreenFromRasterFlipsYAndMapsOnce) {
  const auto c = screen_from_raster(0.0, 0.0, 640, 480);
  EXPECT_EQ(c.x, -1.0);
  EXPECT_EQ(c.y, 1.0);  // raster top-left is screen top-left (y up)
  const auto m = screen_from_raster(320.0, 240.0, 640, 480);
  EXPECT_EQ(m.x, 0.0);
  EXPECT_EQ(m.y, 0.0);
  const auto e = screen_from_raster(640.0, 480.0, 640, 480);
  EXPECT_EQ(e.x, 1.0);
  EXPECT_EQ(e.y, -1.0);
}

TEST(Camera, PerspectiveCentreLooksAlongMinusW) {
  const Vec3<double> eye{1, 2, 3}, target{4, -2, 3};
  auto cam = PerspectiveCamera<double>::look_at(2, 2, std::numbers::pi / 3, eye, target, {0, 0, 1});
  // With an even image the centre lies between pixels; use raster coordinates directly.
  const auto s = screen_from_raster(1.0, 1.0, 2, 2);
  const Vec3<double> d = cam.world_from_camera.vector(cam.camera_direction(s));
  const Vec3<double> want = normalize(target - eye);
  EXPECT_NEAR(dot(normalize(d), want), 1.0, 1e-15);
  EXPECT_EQ(cam.generate(0, 0).o, eye);
}

TEST(Camera, PerspectiveImageCornersAtAspectTimesTanHalfFov) {
  const double fov = std::numbers::pi / 2;  // tan(fov/2) = 1
  PerspectiveCamera<double> cam{400, 200, fov, {}};
  const double h = std::tan(fov / 2), a = 2.0;
  const auto tl = cam.camera_direction(screen_from_raster(0.0, 0.0, 400, 200));
  EXPECT_NEAR(tl.x, -a * h, 1e-15);
  EXPECT_NEAR(tl.y, h, 1e-15);
  EXPECT_EQ(tl.z, -1.0);
  const auto br = cam.camera_direction(screen_from_raster(400.0, 200.0, 400, 200));
  EXPECT_NEAR(br.x, a * h, 1e-15);
  EXPECT_NEAR(br.y, -h, 1e-15);
  // Pixel (0,0)'s centre is half a pixel in from the corner.
  const auto p00 = cam.generate(0, 0).d;
  EXPECT_NEAR(p00.x, -a * h * (1 - 1.0 / 400), 1e-15);
  EXPECT_NEAR(p00.y, h * (1 - 1.0 / 200), 1e-15);
}

TEST(Camera, OrthographicRaysAreParallelAndStartOnTheImagePlane) {
  OrthographicCamera<double> cam{4, 2, look_at<double>({0, 0, 10}, {0, 0, 0}, {0, 1, 0}), -2, 2, -1, 1};
  const auto r00 = cam.generate(0, 0), r31 = cam.generate(3, 1);
  EXPECT_EQ(r00.d, r31.d);
  EXPECT_EQ(r00.d, (Vec3<double>{0, 0, -1}));
  EXPECT_EQ(r00.o.z, 10.0);
  EXPECT_EQ(r31.o.z, 10.0);
  EXPECT_DOUBLE_EQ(r00.o.x, -1.5);  // l + (r - l) * 0.5 / 4
  EXPECT_DOUBLE_EQ(r00.o.y, 0.5);   // top row: t - (t - b) * 0.5 / 2
  EXPECT_DOUBLE_EQ(r31.o.x, 1.5);
  EXPECT_DOUBLE_EQ(r31.o.y, -0.5);
}
