// fuzz --winding's checker (verify/winding_fuzz.h): it judges one point's answers right, it catches
// deliberately wrong answers fed to a campaign (a flipped side, a value off its bound, a surface
// point not reported), and with the library's answers a short campaign finds nothing.
#include "verify/winding_fuzz.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using rayproof::Side;
using rayproof::WindingValue;
using rayproof::verify::judge_winding_point;
using rayproof::verify::run_winding_fuzz;
using rayproof::verify::WindingFuzzOptions;

WindingValue value(double w, double bound) {
  WindingValue v;
  v.w = w, v.bound = bound;
  return v;
}

WindingValue surface() {
  WindingValue v;
  v.surface = true, v.bound = 0;
  return v;
}

TEST(WindingFuzz, JudgesOnePoint) {
  // Right answers: inside, outside, surface.
  auto v = judge_winding_point(value(0.75, 1e-30), value(0.75 + 1e-9, 1e-8), Side::inside);
  EXPECT_TRUE(v.what.empty()) << v.what;
  v = judge_winding_point(value(-2e-7, 1e-30), value(0, 1e-6), Side::outside);
  EXPECT_TRUE(v.what.empty()) << v.what;
  v = judge_winding_point(surface(), surface(), Side::surface);
  EXPECT_TRUE(v.what.empty()) << v.what;
  // The wrong side (w = 0.75 is inside).
  v = judge_winding_point(value(0.75, 1e-30), value(0.75, 1e-8), Side::outside);
  EXPECT_TRUE(v.wrong_side);
  EXPECT_FALSE(v.bound_miss);
  EXPECT_NE(v.what.find("contains says outside"), std::string::npos) << v.what;
  // A value whose interval misses the reference's, on the right side.
  v = judge_winding_point(value(0.75, 1e-30), value(0.75 + 2e-8, 1e-8), Side::inside);
  EXPECT_TRUE(v.bound_miss);
  EXPECT_FALSE(v.wrong_side);
  // Surface in one and not the other, both ways.
  EXPECT_TRUE(judge_winding_point(surface(), value(0.5, 0.1), Side::outside).wrong_surface);
  EXPECT_TRUE(judge_winding_point(surface(), surface(), Side::inside).wrong_surface);
  EXPECT_TRUE(judge_winding_point(value(1, 0), value(1, 0), Side::surface).wrong_surface);
  EXPECT_TRUE(judge_winding_point(value(1, 0), surface(), Side::inside).wrong_surface);
  // Within 1e-6 of 1/2 the side is not judged; the value still is.
  v = judge_winding_point(value(0.5 + 5e-7, 1e-30), value(0.5 + 5e-7, 1e-9), Side::outside);
  EXPECT_TRUE(v.near_half);
  EXPECT_FALSE(v.wrong_side);
  EXPECT_TRUE(v.what.empty()) << v.what;
  v = judge_winding_point(value(0.5 + 2e-6, 1e-30), value(0.5 + 2e-6, 1e-9), Side::outside);
  EXPECT_FALSE(v.near_half);
  EXPECT_TRUE(v.wrong_side);
  // A NaN value off the surface is a bound miss.
  EXPECT_TRUE(judge_winding_point(value(0.2, 0), value(std::nan(""), 0), Side::outside).bound_miss);
}

WindingFuzzOptions short_campaign() {
  WindingFuzzOptions opt;
  opt.max_meshes = 40;
  opt.seed = 5;
  return opt;
}

TEST(WindingFuzz, LibraryAnswersPass) {
  const auto r = run_winding_fuzz(short_campaign());
  EXPECT_EQ(r.meshes, 40u);
  EXPECT_EQ(r.points, 40u * 28);
  EXPECT_GT(r.surface_points, 0u);
  std::size_t kinds = 0;
  for (auto n : r.kind_meshes) kinds += n > 0;
  EXPECT_GE(kinds, 5u);
  EXPECT_EQ(r.failures(), 0u);
  EXPECT_GT(r.batch_meshes, 0u);
  EXPECT_EQ(r.batch_points, r.batch_meshes * rayproof::verify::kWindingBatchCompared);
  for (const auto& f : r.findings) ADD_FAILURE() << f.what << "\n" << f.off;
  // The same seed draws the same campaign.
  const auto again = run_winding_fuzz(short_campaign());
  EXPECT_EQ(again.triangles, r.triangles);
  EXPECT_EQ(again.surface_points, r.surface_points);
}

TEST(WindingFuzz, CatchesAFlippedSide) {
  auto opt = short_campaign();
  // Inside reported as outside: every inside point of the campaign is a finding.
  opt.contains = [](const rayproof::ExactMesh& m, const rayproof::Vec3<double>& p) {
    const Side s = m.contains(p);
    return s == Side::inside ? Side::outside : s;
  };
  const auto r = run_winding_fuzz(opt);
  EXPECT_GT(r.wrong_sides, 0u);
  EXPECT_EQ(r.bound_misses, 0u);
  EXPECT_EQ(r.wrong_surfaces, 0u);
  ASSERT_FALSE(r.findings.empty());
  EXPECT_NE(r.findings.front().what.find("contains says outside"), std::string::npos) << r.findings.front().what;
  EXPECT_NE(r.findings.front().off.find("OFF\n"), std::string::npos);
}

TEST(WindingFuzz, CatchesAValueOffItsBound) {
  auto opt = short_campaign();
  opt.value = [](const rayproof::ExactMesh& m, const rayproof::Vec3<double>& p) {
    WindingValue v = m.winding_value(p);
    if (!v.surface) v.w += 3 * v.bound + 1e-9;  // within 1e-6 of the truth where bounds are small
    return v;
  };
  const auto r = run_winding_fuzz(opt);
  // Every point off the surface, but those whose reference bound exceeds the shift.
  EXPECT_GE(r.bound_misses * 10, (r.points - r.surface_points) * 9);
  EXPECT_LE(r.bound_misses, r.points - r.surface_points);
  EXPECT_EQ(r.wrong_sides, 0u);
}

TEST(WindingFuzz, CatchesAMissedSurface) {
  auto opt = short_campaign();
  opt.contains = [](const rayproof::ExactMesh& m, const rayproof::Vec3<double>& p) {
    const Side s = m.contains(p);
    return s == Side::surface ? Side::outside : s;
  };
  const auto r = run_winding_fuzz(opt);
  EXPECT_EQ(r.wrong_surfaces, r.surface_points);
  EXPECT_GT(r.wrong_surfaces, 0u);
}

TEST(WindingFuzz, CatchesABatchThatDiffersFromSinglePoints) {
  auto opt = short_campaign();
  // The batch flips the side of every eighth point it answers inside or outside.
  opt.batch = [](const rayproof::ExactMesh& m, std::span<const rayproof::Vec3<double>> p, std::span<Side> out) {
    m.contains(p, out, 1);
    for (std::size_t k = 0; k < out.size(); k += 8)
      if (out[k] == Side::inside || out[k] == Side::outside) out[k] = out[k] == Side::inside ? Side::outside : Side::inside;
  };
  const auto r = run_winding_fuzz(opt);
  EXPECT_GT(r.batch_differ, r.batch_points / 8 / 2);
  EXPECT_LE(r.batch_differ, r.batch_points / 8);
  EXPECT_EQ(r.wrong_sides, 0u);
  bool named = false;
  for (const auto& f : r.findings) named = named || f.what.find("the batch says") != std::string::npos;
  EXPECT_TRUE(named);
}

}  // namespace
