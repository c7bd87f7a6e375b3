#pragma once
/// GoogleTest helper: an all-hits function on a mesh against exact crossings
/// (rayproof/verify/crossings_check.h). The test links GTest and rayproof::caster_check.
///
///   auto mine = [&](auto origins, auto directions, auto hits) { my_engine.all_hits(origins, directions, hits); };
///   EXPECT_CROSSINGS_MATCH_EXACT(mine, (rayproof::verify::CasterMesh{vertices, triangles}));
///   ASSERT_CROSSINGS_MATCH_EXACT(mine, mesh);
///
/// It passes when check_crossings finds nothing (CrossingsTally::findings() == 0: no crossing
/// missing or reported twice, no touch reported, no hit without a contact, t within max_ulps, in
/// order, no exception) on the default ray sets; a failure prints the counts and the one-line
/// reproducers.
#include <gtest/gtest.h>

#include "rayproof/verify/crossings_check.h"

namespace rayproof::gtest {

/// The check behind EXPECT_CROSSINGS_MATCH_EXACT.
inline ::testing::AssertionResult crossings_match_exact(const verify::CrossingsFunction& fn,
                                                        const verify::CasterMesh& mesh,
                                                        const verify::CrossingsCheckOptions& opt = {}) {
  const verify::CrossingsTally tally = verify::check_crossings(fn, mesh, opt);
  if (tally.findings() == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "the all-hits function differs from exact on " << tally.findings()
                                       << " counts over " << tally.rays << " rays:\n"
                                       << verify::summary_text(tally);
}

}  // namespace rayproof::gtest

/// Non-fatal / fatal check that the function answers every ray set on the mesh as exact arithmetic does.
#define EXPECT_CROSSINGS_MATCH_EXACT(fn, mesh) EXPECT_TRUE(::rayproof::gtest::crossings_match_exact(fn, mesh))
#define ASSERT_CROSSINGS_MATCH_EXACT(fn, mesh) ASSERT_TRUE(::rayproof::gtest::crossings_match_exact(fn, mesh))
