/// rayproof verify [--methods LIST] [--json] [--mismatches N] FILE: every method against exact,
/// per method x family.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/input.h"
#include "registry/registry.h"
#include "cli/user_kernels.h"
#include "verify/differential.h"

namespace rayproof::cli {

namespace {
struct VerifyOptions {
  std::vector<std::string> methods;
  bool json = false;
  std::size_t mismatches = 0;
  std::uint64_t tolerance = 1;
  std::vector<std::string> files;
  UserKernelOptions user;
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
          {"fallbacks", s.fallbacks},
          {"kernel_failures", s.kernel_failures},
          {"coarse", s.coarse},
          {"promised", s.promised},
          {"promise_broken", s.promise_broken},
          {"unjudged", s.unjudged},  // pairs' hit/miss answers on degenerate or invalid pairs (docs/tritri.md)
          {"bary_error_max", s.bary_errors.empty() ? 0.0 : *std::max_element(s.bary_errors.begin(), s.bary_errors.end())}};
}

int run_verify(const VerifyOptions& opt) {
  auto user = make_user_kernels("verify", opt.user);
  if (!user) return 2;
  const auto selected = registry::select_methods("verify", opt.methods, false, *user);
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
  std::vector<std::pair<std::string, KernelFailure>> failures;
  for (const Method* m : methods)
    if (m->take_failures)
      for (auto& f : m->take_failures()) failures.emplace_back(m->name, std::move(f));
  bool any_kernel_failure = false, any_coarse = false;
  for (const auto& m : cmp.methods) {
    const auto t = cmp.total(m);
    any_kernel_failure = any_kernel_failure || t.kernel_failures > 0;
    any_coarse = any_coarse || t.coarse > 0;
  }

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
      mm.push_back({{"method", x.method}, {"case", io::format_case(x.input)}, {"got", io::format_answer(x.got)},
                    {"exact", io::format_result(x.want)}, {"verdict", verify::to_string(x.verdict)}, {"ulps", x.ulps}});
    nlohmann::json kf = nlohmann::json::array();
    for (const auto& [m, f] : failures) kf.push_back({{"method", m}, {"what", f.what}, {"case", io::format_case(f.input)}});
    fmt::print("{}\n", nlohmann::json{{"files", opt.files}, {"cases", cases.size()}, {"rows", rows}, {"mismatches", mm},
                                      {"kernel_failures", kf}, {"kernels", [&] {
                                        nlohmann::json k = nlohmann::json::object();
                                        for (const auto& m : *user) k[m->name] = m->summary;
                                        return k;
                                      }()}}
                           .dump(1));
  } else {
    // User kernels add two columns: kernel failures (not class errors) and coarse answers.
    const bool extra = !user->empty();
    for (const auto& m : *user) fmt::print("# {}: {}\n", m->name, m->summary);  // GPU kernels: the device and driver
    auto row = [&](const std::string& m, const std::string& g, const verify::Stats& s) {
      fmt::print("{:<16} {:<24} {:>7} {:>7} {:>8} {:>9} {:>9} {:>6} {:>8} {:>8} {:>10} {:>9}", m, g, s.cases,
                 s.class_errors(), s.false_hit, s.false_miss, s.wrong_hit_class, s.wrong_class, ulps(s.ulp_quantile(0.5)),
                 ulps(s.ulp_quantile(0.99)), ulps(s.ulp_quantile(1.0)), s.fallbacks);
      if (extra) fmt::print(" {:>8} {:>7}", s.kernel_failures, s.coarse);
      fmt::print("  {}\n", verify::promise_status(s));
    };
    fmt::print("{:<16} {:<24} {:>7} {:>7} {:>8} {:>9} {:>9} {:>6} {:>8} {:>8} {:>10} {:>9}", "method", "family", "cases",
               "errors", "falsehit", "falsemiss", "wronghit", "other", "ulp_med", "ulp_p99", "ulp_max", "fallbacks");
    fmt::print("{}  promise\n", extra ? fmt::format(" {:>8} {:>7}", "kfail", "coarse") : "");
    for (const auto& m : cmp.methods) {
      for (const auto& g : cmp.groups) {
        auto it = cmp.stats.find({m, g});
        if (it == cmp.stats.end()) continue;
        row(m, g, it->second);
      }
      row(m, "(all)", cmp.total(m));
    }
    if (any_coarse) {
      fmt::print("\n# coarse answers (hit/miss): errors are false hits and false misses; t error against the exact first "
                 "contact at t >= 0\n");
      for (const auto& m : cmp.methods) {
        const auto t = cmp.total(m);
        if (!t.coarse) continue;
        fmt::print("{}: {} of {} cases answered coarsely", m, t.coarse, t.cases);
        if (!t.bary_errors.empty())
          fmt::print("; barycentric error (max |b - exact b| over {} triangle hits): max {:.3g}", t.bary_errors.size(),
                     *std::max_element(t.bary_errors.begin(), t.bary_errors.end()));
        fmt::print("\n");
      }
    }
    if (!failures.empty() || any_kernel_failure) {
      fmt::print("\n# kernel failures (kfail, not counted as class errors): one case-file line each, the input as the "
                 "kernel saw it\n");
      for (const auto& [m, f] : failures) fmt::print("{}  # {}: {}\n", io::format_case(f.input), m, f.what);
      for (const auto& m : cmp.methods) {
        std::size_t n = 0;
        for (const auto& [fm, f] : failures) n += fm == m;
        const auto t = cmp.total(m);
        if (t.kernel_failures > n)
          fmt::print("# {}: {} more cases without an answer (the kernel answered 'error', or was dropped after repeated "
                     "failures)\n", m,
                     t.kernel_failures - n);
      }
    }
    if (!cmp.mismatches.empty()) {
      fmt::print("\n# mismatches (first {} per method): one case-file line each, the input as the method saw it\n",
                 opt.mismatches);
      for (const auto& x : cmp.mismatches)
        fmt::print("{}  # {} {}: got {}, exact {}{}\n", io::format_case(x.input), x.method, verify::to_string(x.verdict),
                   io::format_answer(x.got), io::format_result(x.want),
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
  sub->add_option("--methods", opt->methods, "Methods to compare, registered or your --exec/--plugin kernels (default: every registered method but exact; "
                  "your kernels run whether named or not)")
      ->delimiter(',')->allow_extra_args(false);
  sub->add_flag("--json", opt->json, "Print JSON instead of a table");
  sub->add_option("--mismatches", opt->mismatches, "Print the first N disagreeing cases of each method as case lines")
      ->check(CLI::Range(std::size_t{0}, std::size_t{1000000}));
  sub->add_option("--ulp-tolerance", opt->tolerance, "A class-correct case with a larger t error is listed as a mismatch")
      ->capture_default_str();
  add_user_kernel_options(*sub, opt->user);
  sub->add_option("files", opt->files, "Case files, or - for standard input")->required();
  return [opt] { return run_verify(*opt); };
}

}  // namespace rayproof::cli
