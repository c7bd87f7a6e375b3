/// rayproof fuzz: a differential campaign of every chosen method against exact over the case
/// families; mismatches are minimized and written as one-line case files per method and family.
/// With --mesh: mesh-level property fuzzing instead (verify/mesh_fuzz.h): random closed meshes,
/// leak rays at every vertex and edge midpoint, and crossing parity of random rays.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

#include "cli/commands.h"
#include "cli/registry.h"
#include "cli/user_kernels.h"
#include "scene/accel.h"
#include "verify/fuzz_campaign.h"
#include "verify/mesh_fuzz.h"

namespace rayproof::cli {

namespace {
struct FuzzCliOptions {
  std::vector<std::string> methods, families;
  double seconds = 0;
  std::size_t cases = 0;
  std::uint64_t seed = 1;
  int jobs = 1;
  std::string out = "fuzz-findings";
  bool mesh = false;
  UserKernelOptions user;
};

/// Methods that must never leak (and, for certified, never fail parity) in mesh mode.
bool must_not_leak(const std::string& m) { return m == "robust" || m == "certified"; }

int run_mesh_fuzz_cli(const FuzzCliOptions& o) {
  verify::MeshFuzzOptions opt;
  const std::vector<std::string> names =
      o.methods.empty() ? std::vector<std::string>{"float", "double", "watertight-float", "watertight", "robust", "certified"}
                        : o.methods;
  for (const auto& name : names) {
    try {
      opt.methods.push_back(scene::find_scene_method(name, all_methods()));
    } catch (const std::exception& e) {
      fmt::print(stderr, "rayproof fuzz: {}\n", e.what());
      return 2;
    }
  }
  if (!o.families.empty()) {
    fmt::print(stderr, "rayproof fuzz: --families does not apply to --mesh\n");
    return 2;
  }
  opt.seconds = o.seconds;
  opt.max_meshes = o.cases;
  if (opt.seconds <= 0 && opt.max_meshes == 0) opt.seconds = 10;
  opt.seed = o.seed;
  opt.threads = o.jobs;
  const auto res = verify::run_mesh_fuzz(opt);

  fmt::print("{:<18} {:>10} {:>8} {:>11} {:>15}\n", "method", "leak rays", "leaks", "parity rays", "parity failures");
  for (const auto& st : res.stats)
    fmt::print("{:<18} {:>10} {:>8} {:>11} {:>15}\n", st.method, st.leak_rays, st.leaks, st.parity_rays, st.parity_failures);
  fmt::print("\n{} meshes ({} perturbed icospheres, {} convex hulls), {} triangles in {:.1f} s; "
             "{} parity rays with an exact edge or vertex contact set aside\n",
             res.meshes, res.star_meshes, res.hull_meshes, res.triangles, res.seconds, res.contact_rays_set_aside);
  fmt::print("reproduce: rayproof fuzz --mesh --seed {} --cases {}{}\n", o.seed, res.meshes,
             o.methods.empty() ? "" : " --methods " + fmt::format("{}", fmt::join(o.methods, ",")));
  int bad = 0;
  for (const auto& st : res.stats) {
    const bool broken = must_not_leak(st.method) && (st.leaks > 0 || (st.method == "certified" && st.parity_failures > 0));
    if (!broken) continue;
    ++bad;
    fmt::print(stderr, "rayproof fuzz: method '{}' leaked {} times and failed parity {} times\n", st.method, st.leaks,
               st.parity_failures);
    for (const auto& f : res.findings)
      if (f.method == st.method)
        fmt::print(stderr, "  mesh {} ({}): {} ray {} {} {} {} {} {}{}\n", f.mesh,
                   f.shape == verify::MeshShape::star ? "icosphere" : "hull", f.leak ? "leak" : "parity",
                   io::format_double(f.ray.o.x), io::format_double(f.ray.o.y), io::format_double(f.ray.o.z),
                   io::format_double(f.ray.d.x), io::format_double(f.ray.d.y), io::format_double(f.ray.d.z),
                   f.leak ? "" : fmt::format(" ({} crossings)", f.crossings));
  }
  return bad ? 1 : 0;
}

int run_fuzz_cli(const FuzzCliOptions& o) {
  if (o.mesh && (!o.user.exec.empty() || !o.user.plugin.empty())) {
    fmt::print(stderr, "rayproof fuzz: --mesh does not take --exec or --plugin kernels yet\n");
    return 2;
  }
  if (o.mesh) return run_mesh_fuzz_cli(o);
  verify::FuzzOptions opt;
  auto selected = select_methods("fuzz", o.methods, false);
  if (!selected) return 2;
  opt.methods = std::move(*selected);
  auto user = make_user_kernels("fuzz", o.user);
  if (!user) return 2;
  for (const auto& m : *user) opt.methods.push_back(m.get());
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
  opt.progress = [](const verify::FuzzProgress& p) {
    std::string mm;
    for (const auto& [m, n] : p.mismatches) mm += fmt::format(" {}={}", m, n);
    fmt::print(stderr, "\r[{:6.1f}s] {} cases, {:.0f} cases/s; mismatches:{}   ", p.seconds, p.cases,
               p.seconds > 0 ? double(p.cases) / p.seconds : 0.0, mm);
  };
  const auto res = verify::run_fuzz(opt);
  fmt::print(stderr, "\n");

  fmt::print("{:<16} {:<24} {:>9} {:>10} {:>9} {:>9}\n", "method", "family", "cases", "mismatches", "rate %", "fallbacks");
  for (const Method* m : opt.methods) {
    std::size_t total = 0, bad = 0;
    std::uint64_t fb = 0;
    for (const gen::Family* f : opt.families) {
      auto it = res.stats.find({m->name, f->name});
      if (it == res.stats.end() || it->second.cases == 0) continue;
      const std::size_t n = res.mismatches.at({m->name, f->name});
      fmt::print("{:<16} {:<24} {:>9} {:>10} {:>9.4f} {:>9}\n", m->name, f->name, it->second.cases, n,
                 100.0 * double(n) / double(it->second.cases), it->second.fallbacks);
      total += it->second.cases, bad += n, fb += it->second.fallbacks;
    }
    fmt::print("{:<16} {:<24} {:>9} {:>10} {:>9.4f} {:>9}\n", m->name, "(all)", total, bad,
               total ? 100.0 * double(bad) / double(total) : 0.0, fb);
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
  fmt::print("\n{} rounds, {} cases in {:.1f} s; {} findings written under {}/\n", res.rounds, res.cases, res.seconds,
             written, o.out);
  fmt::print("reproduce: rayproof fuzz --seed {} --cases {}{}{}\n", o.seed, res.cases,
             o.methods.empty() ? "" : " --methods " + fmt::format("{}", fmt::join(o.methods, ",")),
             o.families.empty() ? "" : " --families " + fmt::format("{}", fmt::join(o.families, ",")));
  const auto broken = res.broken_promises();
  for (const auto& m : broken) fmt::print(stderr, "rayproof fuzz: method '{}' broke its exactness promise\n", m);
  return broken.empty() ? 0 : 1;
}
}  // namespace

Run add_fuzz(CLI::App& app) {
  auto o = std::make_shared<FuzzCliOptions>();
  auto* sub = app.add_subcommand("fuzz", "Differential fuzz campaign of methods against exact over the case families");
  sub->add_option("--methods", o->methods, "Methods (default: all but exact)")->delimiter(',')->allow_extra_args(false);
  sub->add_option("--families", o->families, "Families (default: all)")->delimiter(',')->allow_extra_args(false);
  auto* secs = sub->add_option("--seconds", o->seconds, "Run this long (stops at a round boundary)")
                   ->check(CLI::Range(0.0, 1e7));
  sub->add_option("--cases", o->cases, "Run this many cases (whole rounds)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{10000000000ULL}))
      ->excludes(secs);
  sub->add_option("--seed", o->seed, "Seed")->capture_default_str();
  sub->add_option("--jobs", o->jobs, "Worker threads")->check(CLI::Range(1, 256))->capture_default_str();
  sub->add_option("--out", o->out, "Directory for the findings")->capture_default_str();
  sub->add_flag("--mesh", o->mesh,
                "Mesh mode: random closed meshes; leak rays at every vertex and edge midpoint and the parity of "
                "random rays' crossings (--cases counts meshes, --jobs threads per query batch)");
  add_user_kernel_options(*sub, o->user);
  return [o] { return run_fuzz_cli(*o); };
}

}  // namespace rayproof::cli
