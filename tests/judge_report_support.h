#pragma once
// The judges' `--out DIR` reports (check --distance, --contains, --crossings) read back: a row of a
// markdown table by its first cell, and the checks each judge's CLI test makes of its report
// against the same run's --json.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cli_support.h"

namespace rayproof::testing {

/// The cells of a markdown table line "| a | b |": {"a", "b"}.
inline std::vector<std::string> markdown_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::size_t at = line.find('|');
  while (at != std::string::npos) {
    const std::size_t next = line.find(" |", at + 1);
    if (next == std::string::npos) break;
    std::string cell = line.substr(at + 1, next - at - 1);
    cell.erase(0, cell.find_first_not_of(' '));
    cells.push_back(cell);
    at = next + 1;
  }
  return cells;
}

/// The row of the `nth` table (0: the first) of `md` whose first cell is `first`, its cells by the
/// table's header; empty when there is no such row.
inline std::map<std::string, std::string> markdown_row(const std::string& md, std::size_t nth, const std::string& first) {
  std::size_t table = 0;
  bool in_table = false;
  std::vector<std::string> header;
  std::size_t at = 0;
  while (at < md.size()) {
    std::size_t end = md.find('\n', at);
    if (end == std::string::npos) end = md.size();
    const std::string line = md.substr(at, end - at);
    at = end + 1;
    const bool row = line.rfind('|', 0) == 0;
    if (row && line.rfind("|-", 0) == 0) continue;  // the header's separator
    if (!row) {
      if (in_table) ++table;
      in_table = false;
      continue;
    }
    if (!in_table) {
      in_table = true;
      header = markdown_cells(line);
      continue;
    }
    if (table != nth) continue;
    const std::vector<std::string> cells = markdown_cells(line);
    if (cells.empty() || cells[0] != first) continue;
    std::map<std::string, std::string> out;
    for (std::size_t k = 0; k < cells.size() && k < header.size(); ++k) out[header[k]] = cells[k];
    return out;
  }
  return {};
}

/// DIR/report.md of a judge's --out against the --json of the same run (`run`: its one function
/// `fn`, judged on one mesh `mesh`; `items`: "points" or "rays"): the function's row holds every
/// count of the JSON under the same key (every one of `keys` among them) and its per-set counts;
/// rayproof's own row judges the same items with 0 findings; both verdict sentences are there.
inline void expect_report_matches_json(const std::filesystem::path& dir, const nlohmann::json& run,
                                       const std::string& fn, const std::string& mesh, const std::string& items,
                                       std::uint64_t differing, const std::vector<std::string>& keys) {
  const std::string md = slurp(dir / "report.md"), html = slurp(dir / "report.html");
  ASSERT_FALSE(md.empty()) << dir;
  EXPECT_NE(html.find("<table>"), std::string::npos);
  EXPECT_NE(html.find(fn + " (" + run["command"].get<std::string>() + ")"), std::string::npos) << html;
  const auto row = markdown_row(md, 0, "**" + fn + "**");
  ASSERT_FALSE(row.empty()) << md;
  EXPECT_EQ(row.at("mesh"), mesh);
  for (const std::string& key : keys) {
    ASSERT_TRUE(row.count(key)) << key << " is no column of\n" << md;
    ASSERT_TRUE(run.contains(key)) << key;
  }
  std::size_t compared = 0;
  for (const auto& [column, cell] : row) {
    if (!run.contains(column) || !run[column].is_number_integer()) continue;
    EXPECT_EQ(cell, std::to_string(run[column].get<std::uint64_t>())) << column << "\n" << md;
    ++compared;
  }
  EXPECT_GE(compared, keys.size());
  EXPECT_EQ(row.at("events"), std::to_string(run["events"].size()));
  EXPECT_NE(row.at("time per query").find(" µs"), std::string::npos) << row.at("time per query");
  EXPECT_NE(row.at("judge cost").find('x'), std::string::npos) << row.at("judge cost");
  const std::uint64_t n = run[items].get<std::uint64_t>();
  EXPECT_NE(md.find("function '" + fn + "' differs from exact on " + std::to_string(differing) + " of " +
                    std::to_string(n) + " " + items + " on " + mesh),
            std::string::npos)
      << md;

  // rayproof's own exact answer, judged the same: the same items, no finding.
  const auto own = markdown_row(md, 0, "rayproof exact");
  ASSERT_FALSE(own.empty()) << md;
  EXPECT_EQ(own.at(items), std::to_string(n));
  EXPECT_EQ(own.at("findings"), "0") << md;
  EXPECT_NE(md.find("function 'rayproof exact' answered all " + std::to_string(n) + " " + items + " on " + mesh),
            std::string::npos)
      << md;

  // Per set: "findings of items", as the JSON's sets.
  const auto sets = markdown_row(md, 1, fn);
  ASSERT_FALSE(sets.empty()) << md;
  const auto own_sets = markdown_row(md, 1, "rayproof exact");
  for (const auto& [name, s] : run["sets"].items()) {
    ASSERT_TRUE(sets.count(name)) << name << "\n" << md;
    EXPECT_EQ(sets.at(name), std::to_string(s["findings"].get<std::uint64_t>()) + " of " +
                                 std::to_string(s[items].get<std::uint64_t>()))
        << name;
    EXPECT_EQ(own_sets.at(name), "0 of " + std::to_string(s[items].get<std::uint64_t>())) << name;
  }
}

/// Runs `args --json --out DIR` (a judge with a function that has findings: exit 1), checks the
/// "wrote" line, and returns the JSON of its first function.
inline nlohmann::json run_writing_report(const std::string& args, const std::filesystem::path& dir) {
  const auto r = run_rayproof(args + " --json --out " + dir.string());
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("wrote " + dir.string() + "/report.md and " + dir.string() + "/report.html"),
            std::string::npos)
      << r.err;
  const nlohmann::json out = nlohmann::json::parse(r.out, nullptr, false);
  EXPECT_FALSE(out.is_discarded()) << r.out;
  return out.is_discarded() ? nlohmann::json::object() : out["functions"][0];
}

/// A --out DIR that cannot be made (a path under a regular file): exit 2, a message naming the report.
inline void expect_unwritable_out_refused(const std::string& args) {
  const auto plain = write_file("plain_file", "not a directory\n");
  const auto r = run_rayproof(args + " --out " + (plain / "sub").string());
  EXPECT_EQ(r.status, 2) << r.err << r.out;
  EXPECT_NE(r.err.find("cannot write " + (plain / "sub" / "report.md").string()), std::string::npos) << r.err;
}

}  // namespace rayproof::testing
