/// rayproof verify [--methods LIST] [--json] [--mismatches N] FILE: every method against exact,
/// per method x family.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/input.h"
#include "cli/registry.h"
#include "verify/differential.h"

namespace rayproof::cli {

namespace {
struct VerifyOptions {
  std::vector<std::string> methods;
  bool json = false;
  std::size_t mismatches = 0;
  std::uint64_t tolerance = 1;
  std::vector<std::string> files;
};

std::string ulps(std::uint64_t u) {
  return u == std::numeric_limits<std::uint64_t>::max() ? std::string("missing") : std::to_string(u);
}

nlohmann::json stats_json(const verify::Stats& s) {
  return {{"cases", s.cases},
          {"class_errors", s.class_errors()},
          {"false_hit", s.false_hit},
          {"false_miss", s.false_miss},
          {"wrong_hit_class", s.wrong_hit_class},
          {"wrong_class", s.wrong_class},
          {"ulp_median", s.ulp_quantile(0.5)},
          {"ulp_p99", s.ulp_quantile(0.99)},
          {"ulp_max", s.ulp_quantile(1.0)},
          {"fallbacks", s.fallbacks}};
}

int run_verify(const VerifyOptions& opt) {
  const auto selected = select_methods("verify", opt.methods, false);
  if (!selected) return 2;
  const std::vector<const Method*>& methods = *selected;
  std::vector<io::Case> cases;
  int errors = 0, bad_files = 0;
  for (const std::string& file : opt.files) {
    CaseInput in = read_case_input(file);
    if (!in.error.empty()) {
      fmt::print(stderr, "rayproof verify: {}\n", in.error);
      ++bad_files;
    }
    for (const auto& e : in.entries) {
      if (const auto* err = std::get_if<io::CaseError>(&e)) {
        fmt::print(stderr, "rayproof verify: {} (skipped)\n", located(file, *err));
        ++errors;
      } else {
        cases.push_back(std::get<io::Case>(e));
      }
    }
  }
  const auto exact = verify::exact_answers(cases);
  const auto cmp = verify::compare(cases, exact, methods, opt.mismatches, opt.tolerance);

  if (opt.json) {
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& m : cmp.methods)
      for (const auto& g : cmp.groups) {
        auto it = cmp.stats.find({m, g});
        if (it == cmp.stats.end()) continue;
        auto j = stats_json(it->second);
        j["method"] = m;
        j["family"] = g;
        rows.push_back(j);
      }
    nlohmann::json mm = nlohmann::json::array();
    for (const auto& x : cmp.mismatches)
      mm.push_back({{"method", x.method}, {"case", io::format_case(x.input)}, {"got", io::format_result(x.got)},
                    {"exact", io::format_result(x.want)}, {"verdict", verify::to_string(x.verdict)}, {"ulps", x.ulps}});
    fmt::print("{}\n", nlohmann::json{{"files", opt.files}, {"cases", cases.size()}, {"rows", rows}, {"mismatches", mm}}.dump(1));
  } else {
    fmt::print("{:<16} {:<24} {:>7} {:>7} {:>8} {:>9} {:>9} {:>6} {:>8} {:>8} {:>10} {:>9}\n", "method", "family", "cases",
               "errors", "falsehit", "falsemiss", "wronghit", "other", "ulp_med", "ulp_p99", "ulp_max", "fallbacks");
    for (const auto& m : cmp.methods) {
      for (const auto& g : cmp.groups) {
        auto it = cmp.stats.find({m, g});
        if (it == cmp.stats.end()) continue;
        const auto& s = it->second;
        fmt::print("{:<16} {:<24} {:>7} {:>7} {:>8} {:>9} {:>9} {:>6} {:>8} {:>8} {:>10} {:>9}\n", m, g, s.cases,
                   s.class_errors(), s.false_hit, s.false_miss, s.wrong_hit_class, s.wrong_class, ulps(s.ulp_quantile(0.5)),
                   ulps(s.ulp_quantile(0.99)), ulps(s.ulp_quantile(1.0)), s.fallbacks);
      }
      const auto t = cmp.total(m);
      fmt::print("{:<16} {:<24} {:>7} {:>7} {:>8} {:>9} {:>9} {:>6} {:>8} {:>8} {:>10} {:>9}\n", m, "(all)", t.cases,
                 t.class_errors(), t.false_hit, t.false_miss, t.wrong_hit_class, t.wrong_class, ulps(t.ulp_quantile(0.5)),
                 ulps(t.ulp_quantile(0.99)), ulps(t.ulp_quantile(1.0)), t.fallbacks);
    }
    if (!cmp.mismatches.empty()) {
      fmt::print("\n# mismatches (first {} per method): one case-file line each, the input as the method saw it\n",
                 opt.mismatches);
      for (const auto& x : cmp.mismatches)
        fmt::print("{}  # {} {}: got {}, exact {}{}\n", io::format_case(x.input), x.method, verify::to_string(x.verdict),
                   io::format_result(x.got), io::format_result(x.want),
                   x.verdict == verify::Verdict::agree ? fmt::format(" ({} ulps)", ulps(x.ulps)) : "");
    }
  }
  if (bad_files) return 2;
  return errors ? 1 : 0;
}
}  // namespace

Run add_verify(CLI::App& app) {
  auto opt = std::make_shared<VerifyOptions>();
  auto* sub = app.add_subcommand("verify", "Compare methods with exact arithmetic on a case file, per method x family");
  sub->add_option("--methods", opt->methods, "Methods to compare (default: every registered method but exact)")
      ->delimiter(',')->allow_extra_args(false);
  sub->add_flag("--json", opt->json, "Print JSON instead of a table");
  sub->add_option("--mismatches", opt->mismatches, "Print the first N disagreeing cases of each method as case lines")
      ->check(CLI::Range(std::size_t{0}, std::size_t{1000000}));
  sub->add_option("--ulp-tolerance", opt->tolerance, "A class-correct case with a larger t error is listed as a mismatch")
      ->capture_default_str();
  sub->add_option("files", opt->files, "Case files, or - for standard input")->required();
  return [opt] { return run_verify(*opt); };
}

}  // namespace rayproof::cli
