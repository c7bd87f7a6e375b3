/// rayproof classify [--method NAME] FILE: one result line per case (docs/cases.md).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "cli/input.h"
#include "registry/registry.h"

namespace rayproof::cli {

namespace {
struct ClassifyOptions {
  std::string method = "double";
  std::vector<std::string> files;
};

int run_classify(const ClassifyOptions& opt) {
  const MethodRegistry& reg = registry::all_methods();
  const Method* m = reg.find(opt.method);
  if (!m) {
    fmt::print(stderr, "rayproof classify: unknown method '{}' (known: {})\n", opt.method, reg.names());
    return 2;
  }
  int errors = 0, bad_files = 0;
  std::string out;
  auto flush = [&] {
    std::fwrite(out.data(), 1, out.size(), stdout);
    out.clear();
  };
  // Each file is answered on its own: a bad file is reported and the next one still processed.
  for (const std::string& file : opt.files) {
    CaseInput in = read_case_input(file);
    if (!in.error.empty()) {
      fmt::print(stderr, "rayproof classify: {}\n", in.error);
      ++bad_files;
      if (in.entries.empty()) continue;
    }
    for (const auto& e : in.entries) {
      if (const auto* err = std::get_if<io::CaseError>(&e)) {
        fmt::print(stderr, "rayproof classify: {}\n", located(file, *err));
        out += "error - -\n";
        ++errors;
        continue;
      }
      const auto& c = std::get<io::Case>(e);
      if (!m->supports(c.kind)) {
        fmt::print(stderr, "rayproof classify: {}:{}: method '{}' does not handle {}\n", file, c.line, m->name,
                   io::to_string(c.kind));
        out += "error - -\n";
        ++errors;
        continue;
      }
      out += io::format_result(m->run(c));
      out += '\n';
      if (out.size() > (1 << 16)) flush();
    }
    flush();
  }
  if (errors) fmt::print(stderr, "rayproof classify: {} line(s) could not be answered\n", errors);
  if (bad_files) return 2;
  return errors ? 1 : 0;
}
}  // namespace

Run add_classify(CLI::App& app) {
  auto opt = std::make_shared<ClassifyOptions>();
  auto* sub = app.add_subcommand("classify", "Answer every case of a case file: one `CLASS T T2` line per case");
  sub->add_option("--method,-m", opt->method, "Method name (see `rayproof methods`)")->capture_default_str();
  sub->add_option("files", opt->files, "Case files, or - for standard input")->required();
  return [opt] { return run_classify(*opt); };
}

}  // namespace rayproof::cli
