/// The report's stability part (stability_report.h).
#include "report/stability_report.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include "report/stability_text.h"

namespace rayproof::report {

std::string stability_csv(const verify::StabilityRun& run) {
  std::string s = "knob,method,precision,exponent,cases,class_errors,false_hit,false_miss,wrong_hit_class,wrong_class,"
                  "ulp_median,ulp_max\n";
  for (const auto& c : run.curves)
    for (const auto& t : c.steps) {
      const auto& st = t.stats;
      s += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n", c.knob, c.method,
                       c.precision == Precision::float32 ? "float" : "double", t.exponent, st.cases, st.class_errors(),
                       st.false_hit, st.false_miss, st.wrong_hit_class, st.wrong_class, st.ulp_quantile(0.5),
                       st.ulp_quantile(1.0));
    }
  return s;
}

std::string write_stability(const verify::StabilityRun& run, const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return dir + ": cannot create directory (" + ec.message() + ")";
  const std::pair<const char*, std::string> files[] = {{"stability.md", "# rayproof: stability\n\n" + stability_markdown(run)},
                                                       {"stability.csv", stability_csv(run)},
                                                       {"stability.svg", stability_svg(run)}};
  for (const auto& [name, text] : files) {
    const auto path = std::filesystem::path(dir) / name;
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) return path.string() + ": cannot write";
  }
  return "";
}

}  // namespace rayproof::report
namespace rayproof::report {
std::string stability_svg(const verify::StabilityRun&) { return ""; }
std::string stability_markdown(const verify::StabilityRun&) { return ""; }
}
