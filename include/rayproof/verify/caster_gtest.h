#pragma once
/// GoogleTest helper: a whole caster (BVH and all) on a mesh against exact answers
/// (rayproof/verify/caster_check.h). The test links GTest and rayproof::caster_check.
///
///   auto mine = [&](auto o, auto d, auto t, auto tri) { my_engine.cast(o, d, t, tri); };
///   EXPECT_CASTER_MATCHES_EXACT(mine, (rayproof::verify::CasterMesh{vertices, triangles}));
///   ASSERT_CASTER_MATCHES_EXACT(mine, mesh);
///
/// It passes when check_caster finds nothing (CasterTally::findings() == 0: no false miss, false
/// hit, wrong triangle, t error above 1 ulp, garbage answer, exception, or hit on an invalid ray),
/// on the default ray sets and options; a failure prints the counts and the one-line reproducers.
#include <gtest/gtest.h>

#include "rayproof/verify/caster_check.h"

namespace rayproof::gtest {

/// The check behind EXPECT_CASTER_MATCHES_EXACT.
inline ::testing::AssertionResult caster_matches_exact(const verify::ClosestCaster& caster,
                                                       const verify::CasterMesh& mesh,
                                                       const verify::CasterCheckOptions& opt = {}) {
  const verify::CasterTally tally = verify::check_caster(caster, mesh, opt);
  if (tally.findings() == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "the caster differs from exact on " << tally.findings() << " of "
                                       << tally.rays << " rays:\n"
                                       << verify::summary_text(tally);
}

}  // namespace rayproof::gtest

/// Non-fatal / fatal check that the caster answers every ray set on the mesh as exact arithmetic does.
#define EXPECT_CASTER_MATCHES_EXACT(caster, mesh) EXPECT_TRUE(::rayproof::gtest::caster_matches_exact(caster, mesh))
#define ASSERT_CASTER_MATCHES_EXACT(caster, mesh) ASSERT_TRUE(::rayproof::gtest::caster_matches_exact(caster, mesh))
