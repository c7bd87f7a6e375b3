#pragma once
/// GoogleTest helper: a containment (inside/outside) function on a mesh against exact answers
/// (rayproof/verify/contains_check.h). The test links GTest and rayproof::caster_check.
///
///   auto mine = [&](auto points, auto side) { my_engine.contains(points, side); };  // 0, 1, 2
///   EXPECT_CONTAINS_MATCHES_EXACT(mine, (rayproof::verify::ContainsMesh{vertices, triangles}));
///   ASSERT_CONTAINS_MATCHES_EXACT(mine, mesh);
///
/// It passes when check_contains finds nothing (ContainsTally::findings() == 0: no inside called
/// outside or the reverse, no surface answer off the surface, no garbage, no exception) on the
/// default point sets and rule; a failure prints the counts and the one-line reproducers.
#include <gtest/gtest.h>

#include "rayproof/verify/contains_check.h"

namespace rayproof::gtest {

/// The check behind EXPECT_CONTAINS_MATCHES_EXACT.
inline ::testing::AssertionResult contains_matches_exact(const verify::ContainsFunction& fn,
                                                         const verify::ContainsMesh& mesh,
                                                         const verify::ContainsCheckOptions& opt = {}) {
  const verify::ContainsTally tally = verify::check_contains(fn, mesh, opt);
  if (tally.findings() == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "the containment function differs from exact on " << tally.findings()
                                       << " of " << tally.points << " points:\n"
                                       << verify::summary_text(tally);
}

}  // namespace rayproof::gtest

/// Non-fatal / fatal check that the function answers every point set on the mesh as exact arithmetic does.
#define EXPECT_CONTAINS_MATCHES_EXACT(fn, mesh) EXPECT_TRUE(::rayproof::gtest::contains_matches_exact(fn, mesh))
#define ASSERT_CONTAINS_MATCHES_EXACT(fn, mesh) ASSERT_TRUE(::rayproof::gtest::contains_matches_exact(fn, mesh))
