#pragma once
// Runs the rayproof binary in a shell and captures exit status, stdout and stderr.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace rayproof::testing {

struct RunResult {
  int status = -1;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// This process's scratch directory under the system's temporary directory, removed when the
/// process exits (each test runs in its own process: without this, every run left its files).
inline std::filesystem::path scratch_dir() {
  struct RemoveAtExit {
    std::filesystem::path dir;
    pid_t owner = ::getpid();
    ~RemoveAtExit() {
      if (::getpid() != owner) return;  // a forked child exiting leaves its parent's files alone
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  };
  static const RemoveAtExit scratch{std::filesystem::temp_directory_path() /
                                    ("rayproof_test_" + std::to_string(::getpid()))};
  std::filesystem::create_directories(scratch.dir);
  return scratch.dir;
}

inline std::filesystem::path write_file(const std::string& name, const std::string& text) {
  auto p = scratch_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

/// Runs `PREFIX BIN ARGS` (shell text; PREFIX e.g. limits or `timeout`) and captures everything.
inline RunResult run_program(const std::string& bin, const std::string& args, const std::string& stdin_text = "",
                             const std::string& prefix = "") {
  const auto dir = scratch_dir();
  const auto in = dir / "stdin.txt", out = dir / "stdout.txt", err = dir / "stderr.txt";
  std::ofstream(in, std::ios::binary) << stdin_text;
  const std::string cmd = prefix + bin + " " + args + " <" + in.string() + " >" + out.string() + " 2>" + err.string();
  const int raw = std::system(cmd.c_str());
  RunResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

/// Runs `PREFIX rayproof ARGS` and captures everything.
inline RunResult run_rayproof(const std::string& args, const std::string& stdin_text = "",
                              const std::string& prefix = "") {
  return run_program(RAYPROOF_BIN, args, stdin_text, prefix);
}

/// The unit cube [0, 1]^3 as an OFF file, 12 outward-facing triangles (the CLI judges' tests).
inline const std::string kUnitCubeOff = R"(OFF
8 12 0
0 0 0
1 0 0
0 1 0
1 1 0
0 0 1
1 0 1
0 1 1
1 1 1
3 0 2 3
3 0 3 1
3 4 5 7
3 4 7 6
3 0 1 5
3 0 5 4
3 2 6 7
3 2 7 3
3 0 4 6
3 0 6 2
3 1 3 7
3 1 7 5
)";

/// Whether /usr/bin/python3 imports numpy (the Python examples need it).
inline bool have_numpy() { return std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") == 0; }

/// The value of `key` in a `check` text summary, in the block that `block` opens (e.g. "caster 'mt'",
/// "function 'np'": the first mesh it ran on); size_t(-1) when either is missing.
inline std::size_t summary_count(const std::string& out, const std::string& block, const std::string& key) {
  const auto at = out.find(block);
  if (at == std::string::npos) return std::size_t(-1);
  const auto k = out.find("\n" + key + " ", at);
  if (k == std::string::npos) return std::size_t(-1);
  return std::stoul(out.substr(out.find_first_not_of(' ', k + key.size() + 1)));
}

}  // namespace rayproof::testing
