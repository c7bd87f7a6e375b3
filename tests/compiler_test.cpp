// Guards against a g++ 12.2 -O3 miscompilation: in SLP-vectorized code a double -> float -> double
// round trip came back unrounded, so "float inputs" were not floats (found by the case generator
// and the mesh fuzzer). rayproof::core turns basic-block vectorization off under GCC; this test
// fails if that protection goes away.
#include <gtest/gtest.h>

#include <array>

#include "rayproof/vec3.h"

namespace {
struct Triple {
  double x, y, z;
};

__attribute__((noinline)) Triple scaled(double h, int k) {
  return {h * 0.1234567891234 * k, h * 0.98765432123 * k, h * 0.55555555557 * k};
}

__attribute__((noinline)) std::array<double, 12> rounded_points(double sc) {
  auto to_float = [&](double h, int k) {
    const Triple v = scaled(h * sc, k);
    return std::array<float, 3>{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
  };
  const auto o = to_float(4, 1);
  const std::array<std::array<float, 3>, 3> tri{to_float(1, 2), to_float(1, 3), to_float(1, 4)};
  std::array<double, 12> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    out[i] = o[i];
    for (std::size_t k = 0; k < 3; ++k) out[3 + 3 * k + i] = tri[k][i];
  }
  return out;
}
}  // namespace

TEST(Compiler, FloatRoundTripsSurviveOptimization) {
  const auto v = rounded_points(1000.0);
  for (std::size_t i = 0; i < v.size(); ++i) {
    volatile float f = static_cast<float>(v[i]);
    EXPECT_EQ(static_cast<double>(f), v[i]) << "value " << i << " is not a float";
  }
}

TEST(Compiler, Vec3CastRoundsToFloat) {
  volatile double x = 3.0561825402958998, y = -0.93630612988445516, z = 2.99870276;
  const rayproof::Vec3<double> p{x, y, z};
  const rayproof::Vec3<double> q = p.cast<float>().cast<double>();
  for (int i = 0; i < 3; ++i) {
    volatile float f = static_cast<float>(p[i]);
    EXPECT_EQ(q[i], static_cast<double>(f));
  }
}
