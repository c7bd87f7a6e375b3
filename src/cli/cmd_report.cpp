/// rayproof report: the main job. Generates every case family, runs every method, compares with
/// exact, times all methods side by side, and writes report.md, report.csv, error_vs_time.svg.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <chrono>
#include <fstream>
#include <functional>
#include <memory>

#include "cli/commands.h"
#include "cli/input.h"
#include "registry/registry.h"
#include "cli/user_kernels.h"
#include "gen/families.h"
#include "report/report.h"
#include "report/report_text.h"
#include "report/html.h"
#include "report/irradiance_sweep.h"
#include "report/stability_report.h"
#include "gen/knobs.h"
#include "verify/stability.h"

namespace rayproof::cli {

namespace {
struct ReportOptions {
  std::size_t count = 2000;
  /// Cases per triangle-pair family (tritri_*): CGAL's exact pair test is about 100 us, so pairs get
  /// fewer cases than rays to keep the report's run time (docs/tritri.md).
  std::size_t pair_count = 100;
  std::uint64_t seed = 1;
  std::string out = "report";
  std::vector<std::string> methods;
  std::vector<std::string> families;
  std::string input;
  UserKernelOptions user;
  std::uint64_t irradiance_samples = 16384;
  std::uint64_t ulp_tolerance = 1;
  bool stability_only = false;        ///< --stability: only the stability part
  std::size_t stability_count = 200;  ///< cases per knob step (0: no stability part)
  bool stability_count_given = false; ///< --stability-count on the command line
};

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

/// The stability part (docs/stability.md): stability.md, .csv, .svg, and, when `append_to` names a
/// file, its markdown section appended there.
std::string run_stability_part(const ReportOptions& opt, const std::vector<const Method*>& methods,
                               const std::function<void(const std::string&)>& progress, const std::string& append_to) {
  std::vector<const gen::Knob*> knobs;
  for (const auto& k : gen::knobs()) knobs.push_back(&k);
  const auto run = verify::run_stability(knobs, methods, opt.stability_count, opt.seed, progress);
  if (auto err = report::write_stability(run, opt.out); !err.empty()) return err;
  if (!append_to.empty()) {
    std::ofstream out(append_to, std::ios::binary | std::ios::app);
    out << "\n" << report::stability_markdown(run);
    if (!out) return append_to + ": cannot write";
  }
  progress(fmt::format("wrote {0}/stability.md, {0}/stability.csv, {0}/stability.svg", opt.out));
  return "";
}

int run_report(const ReportOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  auto progress = [&](const std::string& msg) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print(stderr, "[{:6.1f}s] {}\n", s, msg);
  };
  auto user = make_user_kernels("report", opt.user);
  if (!user) return 2;
  const auto selected = registry::select_methods("report", opt.methods, true, *user);
  if (!selected) return 2;
  const std::vector<const Method*>& methods = *selected;

  if (opt.stability_only) {
    if (opt.stability_count == 0) {
      fmt::print(stderr, "rayproof report: --stability needs --stability-count of at least 1\n");
      return 2;
    }
    if (auto err = run_stability_part(opt, methods, progress, ""); !err.empty()) {
      fmt::print(stderr, "rayproof report: {}\n", err);
      return 2;
    }
    return 0;
  }

  std::vector<io::Case> cases;
  std::vector<std::string> notes;
  for (const auto& m : *user) notes.push_back(fmt::format("kernel {}: {}", m->name, m->summary));  // names a GPU device
  if (!opt.input.empty()) {
    CaseInput in = read_case_input(opt.input);
    if (!in.error.empty() && in.entries.empty()) {
      fmt::print(stderr, "rayproof report: {}\n", in.error);
      return 2;
    }
    for (const auto& e : in.entries)
      if (const auto* c = std::get_if<io::Case>(&e)) cases.push_back(*c);
    notes.push_back(fmt::format("cases: {} from `{}`", cases.size(), opt.input));
  } else {
    std::vector<const gen::Family*> fams;
    if (opt.families.empty()) {
      for (const auto& f : gen::families()) fams.push_back(&f);
    } else {
      for (const auto& name : opt.families) {
        const gen::Family* f = gen::find_family(name);
        if (!f) {
          fmt::print(stderr, "rayproof report: unknown family '{}' (see `rayproof gen --list`)\n", name);
          return 2;
        }
        fams.push_back(f);
      }
    }
    progress(fmt::format("generating {} families x {} cases (seed {})", fams.size(), opt.count, opt.seed));
    // Half the cases are built in float (exact contacts stay exact for float methods), half in double.
    std::size_t pair_families = 0;
    for (const gen::Family* f : fams) {
      const bool pair = f->kind == io::Kind::tritri;
      pair_families += pair ? 1 : 0;
      const std::size_t count = pair ? opt.pair_count : opt.count;
      for (auto p : {gen::Precision::float32, gen::Precision::float64}) {
        const std::size_t n = p == gen::Precision::float32 ? count / 2 : count - count / 2;
        auto part = gen::generate(*f, n, opt.seed, p);
        cases.insert(cases.end(), part.begin(), part.end());
      }
    }
    if (pair_families < fams.size())
      notes.push_back(fmt::format("cases: {} families x {} (half built in float precision, half in double), seed {}; "
                                  "reproduce with `rayproof gen FAMILY --count {} --seed {} --precision float|double`",
                                  fams.size() - pair_families, opt.count, opt.seed, opt.count / 2, opt.seed));
    if (pair_families > 0)
      notes.push_back(fmt::format("triangle pairs: {} families x {} (--pair-count; fewer than rays, as CGAL's exact "
                                  "pair test takes about 0.1 ms), half built in float precision, half in double, seed {}; "
                                  "reproduce with `rayproof gen FAMILY --count {} --seed {} --precision float|double`",
                                  pair_families, opt.pair_count, opt.seed, opt.pair_count / 2, opt.seed));
  }
  if (cases.empty()) {
    fmt::print(stderr, "rayproof report: no cases\n");
    return 2;
  }
  notes.push_back(fmt::format("methods: {}", [&] {
    std::string s;
    for (const Method* m : methods) s += (s.empty() ? "" : ", ") + m->name;
    return s;
  }()));
  for (const auto& m : *user)
    if (is_glsl_kernel(*m))
      notes.push_back(fmt::format("{} is your {}: its ns/case is the wall time of whole batches (up to 65536 cases "
                                  "per dispatch) divided by their cases, the copies through pipes to its process "
                                  "included", m->name, m->summary));
    else if (m->classify_batch && m->summary.rfind("OpenCL C ", 0) == 0)
      notes.push_back(fmt::format("{} is your OpenCL kernel: its ns/case is the wall time of whole batches divided by "
                                  "their cases, the pipes to its device process, the copies to and from the device "
                                  "and the launch included (the build is not); the device runs a batch on all of its "
                                  "compute units, the CPU methods on one thread",
                                  m->name));
    else if (m->classify_batch)
      notes.push_back(fmt::format("{} is your kernel over --exec: its ns/case is the wall time of a whole batch "
                                  "divided by its cases, the line protocol (formatting, pipes, parsing) and the "
                                  "start of its process included",
                                  m->name));
  notes.push_back(fmt::format("machine: {}, one thread", cpu_model()));

  auto rep = report::build_report(cases, methods, progress);
  rep.notes = notes;
  rep.ulp_tolerance = opt.ulp_tolerance;
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  rep.notes.push_back(fmt::format("run time of the whole report: {:.1f} s", secs));
  if (auto err = report::write_report(rep, opt.out); !err.empty()) {
    fmt::print(stderr, "rayproof report: {}\n", err);
    return 2;
  }
  progress(fmt::format("wrote {0}/report.md, {0}/report.csv, {0}/error_vs_time.svg", opt.out));
  // The stability part belongs to the main job (every family); a focused run (--input, --families)
  // gets it only when --stability-count asks for it.
  const bool focused = !opt.input.empty() || !opt.families.empty();
  if (opt.stability_count > 0 && (!focused || opt.stability_count_given))
    if (auto err = run_stability_part(opt, methods, progress, opt.out + "/report.md"); !err.empty()) {
      fmt::print(stderr, "rayproof report: {}\n", err);
      return 2;
    }
  if (auto err = report::write_irradiance_section(opt.out, methods, registry::all_methods().find("certified"), opt.irradiance_samples,
                                                  opt.seed, progress); !err.empty()) {
    fmt::print(stderr, "rayproof report: {}\n", err);
    return 2;
  }
  // report.html last: it renders the finished report.md (stability and irradiance sections included).
  if (auto err = report::write_html(opt.out); !err.empty()) {
    fmt::print(stderr, "rayproof report: {}\n", err);
    return 2;
  }
  progress(fmt::format("wrote {}/report.html", opt.out));
  fmt::print("{:<16} {:>10} {:>12} {:>12} {:>10}\n", "method", "ns/case", "class err %", "max ulps", "fallback %");
  for (const auto& p : rep.points)
    fmt::print("{:<16} {:>10.1f} {:>12.4f} {:>12} {:>10.3f}\n", p.method, p.ns_per_case, 100 * p.class_error_rate,
               report::ulp_text(p.max_ulps, p.precision),
               100 * p.fallback_rate);
  return 0;
}
}  // namespace

Run add_report(CLI::App& app) {
  auto opt = std::make_shared<ReportOptions>();
  auto* sub = app.add_subcommand("report", "Error against run time of every method on every case family (the main job)");
  sub->add_option("--count", opt->count, "Cases per family")->check(CLI::Range(std::size_t{2}, std::size_t{1000000}))
      ->capture_default_str();
  sub->add_option("--pair-count", opt->pair_count, "Cases per triangle-pair family (tritri_*)")
      ->check(CLI::Range(std::size_t{2}, std::size_t{1000000}))->capture_default_str();
  sub->add_option("--seed", opt->seed, "Seed of the case families")->capture_default_str();
  sub->add_option("--ulp-tolerance", opt->ulp_tolerance,
                  "Error-free: no class error and t within this many ulps (a method's promised tolerance wins)")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{1} << 62))
      ->capture_default_str();
  sub->add_option("--out", opt->out, "Output directory")->capture_default_str();
  sub->add_option("--methods", opt->methods, "Methods, registered or your --exec/--plugin kernels (default: all registered; your "
                  "kernels run whether named or not)")->delimiter(',')->allow_extra_args(false);
  sub->add_option("--families", opt->families, "Families (default: all)")->delimiter(',')->allow_extra_args(false);
  sub->add_option("--input", opt->input, "Use the cases of this file instead of generated families");
  sub->add_flag("--stability", opt->stability_only,
                 "Only the stability part: every method along each stiffness knob (stability.md, .csv, .svg)");
  auto* stability_count = sub->add_option("--stability-count", opt->stability_count,
                  "Cases per step of each stiffness knob (0: no stability part; with --input or --families, only when given)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{5000}))
      ->capture_default_str();
  add_user_kernel_options(*sub, opt->user);
  sub->add_option("--irradiance-samples", opt->irradiance_samples,
                  "Largest sample count of the irradiance section's sweep (0: no irradiance section)")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{1} << 24))->capture_default_str();
  return [opt, stability_count] {
    opt->stability_count_given = stability_count->count() > 0;
    return run_report(*opt);
  };
}

}  // namespace rayproof::cli
