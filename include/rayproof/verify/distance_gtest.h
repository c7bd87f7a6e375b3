#pragma once
/// GoogleTest helper: a distance function on a mesh against exact answers
/// (rayproof/verify/distance_check.h). The test links GTest and rayproof::caster_check.
///
///   auto mine = [&](auto points, auto out) { my_sdf.distance(points, out); };  // doubles
///   EXPECT_DISTANCE_MATCHES_EXACT(mine, (rayproof::verify::ContainsMesh{vertices, triangles}));
///   ASSERT_DISTANCE_MATCHES_EXACT(mine, mesh);
///   // signed, float32, closest points (a DistanceAnswerFunction) or a tolerance: the options
///   verify::DistanceCheckOptions opt;
///   opt.signed_distance = true;
///   EXPECT_TRUE(rayproof::gtest::distance_matches_exact(mine, mesh, opt));
///
/// It passes when check_distance finds nothing (DistanceTally::findings() == 0) on the default
/// point sets; a failure prints the counts and the one-line reproducers.
#include <gtest/gtest.h>

#include "rayproof/verify/distance_check.h"

namespace rayproof::gtest {

namespace detail {
inline ::testing::AssertionResult distance_result(const verify::DistanceTally& tally) {
  if (tally.findings() == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "the distance function differs from exact on " << tally.findings() << " of "
                                       << tally.points << " points:\n"
                                       << verify::summary_text(tally);
}
}  // namespace detail

/// The check behind EXPECT_DISTANCE_MATCHES_EXACT: distances alone.
inline ::testing::AssertionResult distance_matches_exact(const verify::DistanceFunction& fn,
                                                         const verify::ContainsMesh& mesh,
                                                         const verify::DistanceCheckOptions& opt = {}) {
  return detail::distance_result(verify::check_distance(fn, mesh, opt));
}
/// The same for a function answering closest points and triangles too (verify::DistanceAnswer).
inline ::testing::AssertionResult distance_matches_exact(const verify::DistanceAnswerFunction& fn,
                                                         const verify::ContainsMesh& mesh,
                                                         const verify::DistanceCheckOptions& opt = {}) {
  return detail::distance_result(verify::check_distance(fn, mesh, opt));
}

}  // namespace rayproof::gtest

/// Non-fatal / fatal check that the function answers every point set on the mesh as exact arithmetic does.
#define EXPECT_DISTANCE_MATCHES_EXACT(fn, mesh) EXPECT_TRUE(::rayproof::gtest::distance_matches_exact(fn, mesh))
#define ASSERT_DISTANCE_MATCHES_EXACT(fn, mesh) ASSERT_TRUE(::rayproof::gtest::distance_matches_exact(fn, mesh))
