#pragma once
/// A judged program that speaks a line protocol (`check --caster`, `check --contains`; docs/check.md):
/// started under /bin/sh -c in its own process group, fed a header and batches, read one answer
/// line at a time with a timeout. Every failure is returned as a sentence (crashed, exited early,
/// timed out, a line too long), never thrown.
#include <string>

#include "methods/child_process.h"

namespace rayproof::verify {

class LineChild {
 public:
  LineChild() = default;
  LineChild(const LineChild&) = delete;
  LineChild& operator=(const LineChild&) = delete;
  ~LineChild() { stop(true); }
  /// Starts `command` and writes `head`; "" when done, else how it failed.
  std::string start(const std::string& command, const std::string& head, double timeout);
  [[nodiscard]] bool running() const { return ch_.pid > 0; }
  /// "" when `s` is written; else how the program failed. The program's output is read (kept for
  /// line()) while `s` is written, so one that answers as it reads does not block on a full pipe;
  /// the timeout runs from the last byte that moved.
  std::string send(const std::string& s, double timeout);
  /// One answer line into `out`: "", or how the program failed.
  std::string line(std::string& out, double timeout);
  std::string stop(bool kill);

 private:
  std::string ended();
  proc::Child ch_;
  std::string buf_;
};

/// x as the protocols write numbers: shortest round-trip decimal, or inf, -inf, nan.
[[nodiscard]] std::string protocol_number(double x);
/// The first 60 characters of a line, control characters as '?'.
[[nodiscard]] std::string printable(const std::string& s);
/// Ignores SIGPIPE once per process (a program that dies while we write must not kill us).
void ignore_sigpipe();

}  // namespace rayproof::verify
