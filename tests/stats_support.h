#pragma once
// Tally comparison shared by the tests that run one kernel two ways (in process, --exec, plugin).
#include <gtest/gtest.h>

#include <string>

#include "verify/differential.h"

namespace rayproof::testing {

/// The same judged tallies: cases, false hits and misses, wrong classes, t ulps.
inline void expect_same_tallies(const verify::Stats& a, const verify::Stats& b, const std::string& where) {
  EXPECT_EQ(a.cases, b.cases) << where;
  EXPECT_EQ(a.false_hit, b.false_hit) << where;
  EXPECT_EQ(a.false_miss, b.false_miss) << where;
  EXPECT_EQ(a.wrong_hit_class, b.wrong_hit_class) << where;
  EXPECT_EQ(a.wrong_class, b.wrong_class) << where;
  EXPECT_EQ(a.ulps, b.ulps) << where;
}

}  // namespace rayproof::testing
