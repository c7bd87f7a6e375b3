// `rayproof verify` counts disagreements per method x family on a file with known disagreements.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_support.h"

using rayproof::testing::run_rayproof;

namespace {
nlohmann::json row(const nlohmann::json& j, const std::string& method, const std::string& family) {
  for (const auto& r : j["rows"])
    if (r["method"] == method && r["family"] == family) return r;
  ADD_FAILURE() << "no row " << method << " x " << family;
  return {};
}
}  // namespace

TEST(Verify, CountsKnownDisagreements) {
  const auto r = run_rayproof("verify --json --mismatches 10 --methods float,double,certified " +
                              std::string(RAYPROOF_DATA_DIR) + "/known_disagreements.txt");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["cases"], 4);
  auto fm = row(j, "float", "known_false_miss");
  EXPECT_EQ(fm["cases"], 1);
  EXPECT_EQ(fm["false_miss"], 1);
  EXPECT_EQ(fm["class_errors"], 1);
  auto wh = row(j, "double", "known_wrong_hit_class");
  EXPECT_EQ(wh["wrong_hit_class"], 1);
  EXPECT_EQ(wh["false_miss"], 0);
  for (const char* m : {"float", "double", "certified"}) EXPECT_EQ(row(j, m, "known_agree")["class_errors"], 0) << m;
  for (const char* f : {"known_false_miss", "known_wrong_hit_class", "known_agree"})
    EXPECT_EQ(row(j, "certified", f)["class_errors"], 0) << f;
  // Every class mismatch is listed as a one-line reproducer that reads back as a case.
  int class_mismatches = 0;
  for (const auto& m : j["mismatches"]) {
    if (m["verdict"] == "agree") continue;
    ++class_mismatches;
    const auto again = run_rayproof("classify --method exact -", m["case"].get<std::string>() + "\n");
    EXPECT_EQ(again.out, m["exact"].get<std::string>() + "\n");
  }
  EXPECT_EQ(class_mismatches, 2);
}

TEST(Verify, TableListsMismatchesAsCaseLines) {
  const auto r = run_rayproof("verify --mismatches 1 --methods float " + std::string(RAYPROOF_DATA_DIR) +
                              "/known_disagreements.txt");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("triangle -10926396801024.0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("float false-miss: got miss - -, exact edge 274877906944.0 -"), std::string::npos) << r.out;
}
