/// rayproof gen FAMILY|all [--count N] [--seed S] [--precision float|double], rayproof gen --list:
/// deterministic adversarial cases (src/gen/families.h), as a case file with `# family NAME` lines.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <charconv>
#include <cstdio>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "cli/commands.h"
#include "gen/families.h"

namespace rayproof::cli {

namespace {

constexpr unsigned long long kMaxCases = 10'000'000;

struct GenOptions {
  std::string family;
  std::string count = "100";
  std::string seed = "1";
  std::string precision = "double";
  bool list = false;
};

bool parse_u64(const std::string& s, unsigned long long& out) {
  if (s.empty() || s[0] == '-' || s[0] == '+') return false;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

int list_families() {
  std::string out;
  for (const auto& f : gen::families())
    out += fmt::format("{:<24} {:<10} {}\n", f.name, f.every_kind ? "any" : io::to_string(f.kind), f.stresses);
  std::fwrite(out.data(), 1, out.size(), stdout);
  return 0;
}

int run_gen(const GenOptions& opt) {
  if (opt.list) return list_families();
  if (opt.family.empty()) {
    fmt::print(stderr, "rayproof gen: name a family, `all`, or use --list (families: {})\n", gen::family_names());
    return 2;
  }
  std::vector<const gen::Family*> chosen;
  if (opt.family == "all") {
    for (const auto& f : gen::families()) chosen.push_back(&f);
  } else if (const gen::Family* f = gen::find_family(opt.family)) {
    chosen.push_back(f);
  } else {
    fmt::print(stderr, "rayproof gen: unknown family '{}' (known: all, {})\n", opt.family, gen::family_names());
    return 2;
  }
  unsigned long long count = 0;
  if (!parse_u64(opt.count, count) || count < 1 || count > kMaxCases) {
    fmt::print(stderr, "rayproof gen: --count must be a whole number from 1 to {}, got '{}'\n", kMaxCases, opt.count);
    return 2;
  }
  if (count * chosen.size() > kMaxCases) {
    fmt::print(stderr, "rayproof gen: {} families x {} cases is more than {} cases in one run; lower --count\n",
               chosen.size(), count, kMaxCases);
    return 2;
  }
  unsigned long long seed = 0;
  if (!parse_u64(opt.seed, seed)) {
    fmt::print(stderr, "rayproof gen: --seed must be a whole number from 0 to 18446744073709551615, got '{}'\n",
               opt.seed);
    return 2;
  }
  gen::Precision prec;
  if (opt.precision == "double") {
    prec = gen::Precision::float64;
  } else if (opt.precision == "float") {
    prec = gen::Precision::float32;
  } else {
    fmt::print(stderr, "rayproof gen: --precision must be float or double, got '{}'\n", opt.precision);
    return 2;
  }

  std::string out = fmt::format("# rayproof gen {} --count {} --seed {} --precision {}\n", opt.family, count, seed,
                                opt.precision);
  bool write_failed = false;
  auto flush = [&] {
    if (!out.empty() && std::fwrite(out.data(), 1, out.size(), stdout) != out.size()) write_failed = true;
    out.clear();
  };
  for (const gen::Family* f : chosen) {
    out += "# family ";
    out += f->name;
    out += '\n';
    gen::generate_each(*f, static_cast<std::size_t>(count), seed, prec, [&](const io::Case& c) {
      out += io::format_case(c);
      out += '\n';
      if (out.size() > (1 << 16)) flush();
    });
  }
  flush();
  if (write_failed || std::fflush(stdout) != 0) {
    fmt::print(stderr, "rayproof gen: could not write the output\n");
    return 1;
  }
  return 0;
}

}  // namespace

Run add_gen(CLI::App& app) {
  auto opt = std::make_shared<GenOptions>();
  auto* sub = app.add_subcommand("gen", "Generate adversarial cases of a family (deterministic: same seed, same bytes)");
  sub->add_option("family", opt->family, "Family name, or `all` (see --list)");
  sub->add_option("--count,-n", opt->count, "Cases per family, 1 to 10000000")->capture_default_str();
  sub->add_option("--seed,-s", opt->seed, "Seed, an unsigned 64-bit integer")->capture_default_str();
  sub->add_option("--precision,-p", opt->precision, "float: every number exactly a float; or double")
      ->capture_default_str();
  sub->add_flag("--list,-l", opt->list, "List the families: name, kind, what each stresses");
  return [opt] { return run_gen(*opt); };
}

}  // namespace rayproof::cli
