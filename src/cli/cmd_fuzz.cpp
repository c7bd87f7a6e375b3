/// rayproof fuzz: a differential campaign of every chosen method against exact over the case
/// families; mismatches are minimized and written as one-line case files per method and family.
/// With --mesh: mesh-level property fuzzing instead (verify/mesh_fuzz.h): random closed meshes,
/// leak rays at every vertex and edge midpoint, and crossing parity of random rays.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include <unistd.h>

#include "verify/check_text.h"
#include "cli/commands.h"
#include "cli/mesh_modes.h"
#include "cli/tool.h"
#include "cli/fuzz_summary.h"
#include "registry/registry.h"
#include "cli/user_kernels.h"
#include "verify/fuzz_campaign.h"

namespace rayproof::cli {

namespace {

bool write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return bool(out);
}

/// fuzz merge: adds the summaries of a sharded campaign and prints the table of the whole run.
int run_fuzz_merge(const FuzzCliOptions& o) {
  std::vector<FuzzSummary> parts;
  for (const auto& f : o.merge_files) {
    std::ifstream in(f, std::ios::binary);
    if (!in) {
      fmt::print(stderr, "rayproof fuzz merge: {}: cannot read\n", f);
      return 2;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    std::string error;
    auto s = summary_from_json(ss.str(), f, error);
    if (!s) {
      fmt::print(stderr, "rayproof fuzz merge: {}\n", error);
      return 2;
    }
    parts.push_back(std::move(*s));
  }
  std::string error;
  const auto m = merge_summaries(parts, o.merge_files, error);
  if (!m) {
    fmt::print(stderr, "rayproof fuzz merge: {}\n", error);
    return 2;
  }
  fmt::print("{}", fuzz_table(m->campaign.methods, m->campaign.families, m->stats, m->mismatches));
  fmt::print("\n{} rounds, {} cases from {} shards (slowest {:.1f} s)\n", m->rounds, m->cases, m->campaign.shard_count,
             m->seconds);
  if (m->cpu_seconds > 0)
    fmt::print("{:.0f} cases per CPU second ({:.1f} CPU s over the shards)\n", double(m->cases) / m->cpu_seconds,
               m->cpu_seconds);
  if (!o.summary.empty() && !write_text(o.summary, to_json(*m))) {
    fmt::print(stderr, "rayproof fuzz merge: cannot write {}\n", o.summary);
    return 2;
  }
  const auto broken = verify::broken_promises(m->stats);
  for (const auto& name : broken) fmt::print(stderr, "rayproof fuzz merge: method '{}' broke its promise\n", name);
  return broken.empty() ? 0 : 1;
}


int run_fuzz_cli(const FuzzCliOptions& o) {
  if (o.winding) return run_winding_fuzz_cli(o);
  if (o.mesh && o.crossings) return run_crossings_fuzz_cli(o);
  if (o.crossings) {
    fmt::print(stderr, "rayproof fuzz: --crossings goes with --mesh\n");
    return 2;
  }
  if (o.mesh) return run_mesh_fuzz_cli(o);
  if (o.distance) return run_distance_fuzz_cli(o);
  verify::FuzzOptions opt;
  if (!o.shard.empty()) {
    const auto k = parse_shard(o.shard);
    if (!k) {
      fmt::print(stderr, "rayproof fuzz: --shard wants K/N with 1 <= K <= N (e.g. 3/8), not '{}'\n", o.shard);
      return 2;
    }
    opt.shard_index = k->first, opt.shard_count = k->second;
  }
  auto user = make_user_kernels("fuzz", o.user);
  if (!user) return 2;
  for (const auto& k : *user) fmt::print("# {}: {}\n", k->name, k->summary);  // GPU kernels: the device and driver
  auto selected = registry::select_methods("fuzz", o.methods, false, *user);
  if (!selected) return 2;
  opt.methods = std::move(*selected);
  if (o.families.empty()) {
    for (const auto& f : gen::families()) opt.families.push_back(&f);
  } else {
    for (const auto& name : o.families) {
      const gen::Family* f = gen::find_family(name);
      if (!f) {
        fmt::print(stderr, "rayproof fuzz: unknown family '{}' (see `rayproof gen --list`)\n", name);
        return 2;
      }
      opt.families.push_back(f);
    }
  }
  opt.seconds = o.seconds;
  opt.max_cases = o.cases;
  if (opt.seconds <= 0 && opt.max_cases == 0) opt.seconds = 10;
  opt.seed = o.seed;
  opt.jobs = o.jobs;
  // On a terminal one line redrawn every second; in a log (stderr not a terminal) a line of its
  // own every --progress-seconds, never a carriage return.
  const bool tty = isatty(fileno(stderr)) == 1;
  opt.progress_seconds = tty ? 1.0 : o.progress_seconds;
  opt.progress = [tty](const verify::FuzzProgress& p) {
    std::string mm;
    for (const auto& [m, n] : p.mismatches) mm += fmt::format(" {}={}", m, n);
    const std::string line = fmt::format("[{:6.1f}s] {} cases, {:.0f} cases/s; mismatches:{}", p.seconds, p.cases,
                                         p.seconds > 0 ? double(p.cases) / p.seconds : 0.0, mm);
    if (tty) fmt::print(stderr, "\r{}   ", line);
    else fmt::print(stderr, "{}\n", line);
    std::fflush(stderr);
  };
  const auto res = verify::run_fuzz(opt);
  if (tty) fmt::print(stderr, "\n");

  FuzzCampaign campaign;
  campaign.seed = o.seed;
  for (const Method* m : opt.methods) campaign.methods.push_back(m->name);
  for (const gen::Family* f : opt.families) campaign.families.push_back(f->name);
  campaign.batch = opt.batch;
  campaign.max_cases = o.cases;
  campaign.shard_count = opt.shard_count;
  fmt::print("{}", fuzz_table(campaign.methods, campaign.families, res.stats, res.mismatches));
  if (!o.summary.empty() && !write_text(o.summary, to_json(summarize(campaign, opt.shard_index, res)))) {
    fmt::print(stderr, "rayproof fuzz: cannot write {}\n", o.summary);
    return 2;
  }
  // Findings: one file per method and family, one case line each.
  std::error_code ec;
  std::size_t written = 0;
  std::map<std::pair<std::string, std::string>, std::ofstream> files;
  for (const auto& f : res.findings) {
    auto& out = files[{f.method, f.family}];
    if (!out.is_open()) {
      const auto dir = std::filesystem::path(o.out) / f.method;
      std::filesystem::create_directories(dir, ec);
      out.open(dir / (f.family + ".txt"));
      if (!out) {
        fmt::print(stderr, "rayproof fuzz: cannot write {}\n", (dir / (f.family + ".txt")).string());
        return 2;
      }
      out << "# rayproof fuzz findings: method " << f.method << ", family " << f.family << ", seed " << o.seed << "\n";
    }
    out << io::format_case(f.input) << "  # round " << f.round << (f.minimized ? ", minimized" : "") << ": "
        << verify::to_string(f.verdict) << ", got " << io::format_answer(f.got) << ", exact "
        << io::format_result(f.want) << (f.verdict == verify::Verdict::agree ? fmt::format(" ({} ulps)", f.ulps) : "")
        << "\n";
    ++written;
  }
  if (!res.kernel_failures.empty()) {
    fmt::print("\n# kernel failures (counted as mismatches): one case-file line each, the input as the kernel saw it\n");
    for (const auto& [m, f] : res.kernel_failures) fmt::print("{}  # {}: {}\n", io::format_case(f.input), m, f.what);
  }
  fmt::print("\n{} rounds, {}\n{} findings written under {}/ (at most {} per method and family)\n", res.rounds,
             speed_text(res.cases, res.seconds, res.cpu_seconds, opt.jobs), written, o.out, opt.keep_per_group);
  if (opt.shard_count > 1)
    fmt::print("shard {}/{}: rounds {}, {}, ... of the campaign\n", opt.shard_index + 1, opt.shard_count,
               opt.shard_index, opt.shard_index + opt.shard_count);
  fmt::print("reproduce: rayproof fuzz --seed {} --cases {}{}{}{}\n", o.seed, opt.shard_count > 1 && o.cases ? o.cases : res.cases,
             opt.shard_count > 1 ? fmt::format(" --shard {}/{}", opt.shard_index + 1, opt.shard_count) : "",
             o.methods.empty() ? "" : " --methods " + fmt::format("{}", fmt::join(o.methods, ",")),
             o.families.empty() ? "" : " --families " + fmt::format("{}", fmt::join(o.families, ",")));
  const auto broken = res.broken_promises();
  for (const auto& m : broken) fmt::print(stderr, "rayproof fuzz: method '{}' broke its promise\n", m);
  return broken.empty() ? 0 : 1;
}
}  // namespace

Run add_fuzz(CLI::App& app) {
  auto o = std::make_shared<FuzzCliOptions>();
  auto* sub = app.add_subcommand("fuzz", "Differential fuzz campaign of methods against exact over the case families");
  sub->add_option("--methods", o->methods, "Methods, registered or your --exec/--plugin kernels (default: all but exact; your kernels run "
                  "whether named or not)")->delimiter(',')->allow_extra_args(false);
  sub->add_option("--families", o->families, "Families (default: all)")->delimiter(',')->allow_extra_args(false);
  auto* secs = sub->add_option("--seconds", o->seconds, "Run this long (stops at a round boundary)")
                   ->check(CLI::Range(0.0, 1e7));
  sub->add_option("--cases", o->cases, "Run this many cases (whole rounds)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{10000000000ULL}))
      ->excludes(secs);
  sub->add_option("--seed", o->seed, "Seed")->capture_default_str();
  sub->add_option("--jobs", o->jobs, "Worker threads")->check(CLI::Range(1, 256))->capture_default_str();
  sub->add_option("--out", o->out, "Directory for the findings")->capture_default_str();
  sub->add_option("--shard", o->shard,
                  "K/N: run the K-th of N disjoint parts of the campaign (rounds r with r % N = K-1); merge the "
                  "--summary files with `rayproof fuzz merge`");
  sub->add_option("--summary", o->summary, "Write the summary (every method x family tally) as JSON to this file");
  sub->add_option("--progress-seconds", o->progress_seconds,
                  "When stderr is not a terminal (a log), print a progress line every this many seconds")
      ->check(CLI::Range(0.05, 3600.0))
      ->capture_default_str();
  add_user_kernel_options(*sub, o->user);
  auto* merge = sub->add_subcommand("merge", "Add up the --summary files of a sharded campaign (the whole run's counts)");
  merge->add_option("summaries", o->merge_files, "Summary files (fuzz --shard K/N --summary FILE)")->required();
  merge->add_option("--summary", o->summary, "Write the merged summary as JSON to this file");
  sub->add_flag("--mesh", o->mesh,
                "Mesh mode: random closed meshes; leak rays at every vertex and edge midpoint and the parity of "
                "random rays' crossings (--cases counts meshes, --jobs threads per query batch)");
  sub->add_flag("--crossings", o->crossings,
                "With --mesh: fuzz the crossings query instead (every crossing once: net count against the exact "
                "winding number, on rays aimed at every vertex and edge midpoint and random rays)");
  sub->add_flag("--distance", o->distance,
                "Distance mode: random small meshes (ties, zero-area triangles, scales up to 2^+-1000) and points on "
                "and around them; closest points against a brute force in rationals (--cases counts meshes)");
  sub->add_flag("--winding", o->winding,
                "Winding mode (also as --mesh --winding): random open, cracked, holed, flipped, self-overlapping and "
                "closed meshes and soups (scales up to 2^+-300); generalized winding numbers and the winding rule of "
                "contains against a brute force in MPFR (--cases counts meshes)");
  return [o, merge] { return merge->parsed() ? run_fuzz_merge(*o) : run_fuzz_cli(*o); };
}

}  // namespace rayproof::cli
