// The report's numbers are reproducible from `gen` + `verify`, and its files are written.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_support.h"

using rayproof::testing::run_rayproof;
using rayproof::testing::scratch_dir;
using rayproof::testing::slurp;

namespace {
/// CSV rows of the report as maps column -> value.
std::vector<std::map<std::string, std::string>> read_csv(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  for (std::stringstream h(line); std::getline(h, line, ',');) head.push_back(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::stringstream f(line);
    for (const auto& k : head) std::getline(f, row[k], ',');
    rows.push_back(row);
  }
  return rows;
}
}  // namespace

TEST(Report, NumbersAreReproducibleFromGenAndVerify) {
  const auto dir = scratch_dir() / "report_repro";
  const std::string fams = "tri_edge,tri_vertex,tri_near_parallel,tri_far_small,sph_tangent_exact";
  auto r = run_rayproof("report --count 300 --seed 9 --families " + fams + " --methods float,double,robust --out " +
                        dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* f : {"report.md", "report.csv", "error_vs_time.svg"})
    EXPECT_TRUE(std::filesystem::file_size(dir / f) > 200) << f;
  const auto rows = read_csv(slurp(dir / "report.csv"));
  ASSERT_EQ(rows.size(), 15u);

  // The same cases: half built in float precision, half in double, as the report says.
  std::string cases;
  for (const char* p : {"float", "double"}) {
    auto g = run_rayproof("gen all --count 150 --seed 9 --precision " + std::string(p));
    ASSERT_EQ(g.status, 0) << g.err;
    cases += g.out;
  }
  const auto v = run_rayproof("verify --json --methods float,double,robust -", cases);
  ASSERT_EQ(v.status, 0) << v.err;
  const auto j = nlohmann::json::parse(v.out);
  int compared = 0, float_errors = 0;
  for (const auto& row : rows) {
    for (const auto& jr : j["rows"]) {
      if (jr["method"] != row.at("method") || jr["family"] != row.at("family")) continue;
      EXPECT_EQ(std::to_string(jr["cases"].get<long>()), row.at("cases")) << row.at("method") << " " << row.at("family");
      EXPECT_EQ(std::to_string(jr["class_errors"].get<long>()), row.at("class_errors"));
      EXPECT_EQ(std::to_string(jr["false_miss"].get<long>()), row.at("false_miss"));
      EXPECT_EQ(std::to_string(jr["ulp_max"].get<unsigned long>()), row.at("ulp_max"));
      if (row.at("method") == "float") float_errors += std::stoi(row.at("class_errors"));
      ++compared;
    }
  }
  EXPECT_EQ(compared, 15);
  EXPECT_GT(float_errors, 0) << "float must make class errors on exact edges, vertices and tangents";
  const std::string md = slurp(dir / "report.md");
  EXPECT_NE(md.find("## triangle"), std::string::npos);
  EXPECT_NE(md.find("Family by family, the cheapest error-free method is"), std::string::npos);
  // Each method's promise beside its counts (robust promises no false miss ahead on triangles).
  EXPECT_NE(md.find("| promise |"), std::string::npos);
  EXPECT_NE(md.find("`robust` promises no false miss ahead of the origin (coplanar rays excepted) on triangle: kept on all"),
            std::string::npos);
  if (md.find("NaN t |") != std::string::npos) {  // a NaN t in a table is explained, with a reproducer
    EXPECT_NE(md.find("the class was right but t was NaN"), std::string::npos);
  }
}
