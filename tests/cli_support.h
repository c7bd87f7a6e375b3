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

}  // namespace rayproof::testing
