// A judged program speaking a line protocol (verify/line_child.h).
#include "verify/line_child.h"

#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <fmt/core.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>

namespace rayproof::verify {

using Clock = proc::Clock;

std::string protocol_number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return fmt::format("{}", x);
}

std::string printable(const std::string& s) {
  std::string out;
  for (char c : s.substr(0, 60)) out += (static_cast<unsigned char>(c) < 32 || c == 127) ? '?' : c;
  return s.size() > 60 ? out + "..." : out;
}

void ignore_sigpipe() {
  static std::once_flag once;
  std::call_once(once, [] { ::signal(SIGPIPE, SIG_IGN); });
}

std::string LineChild::start(const std::string& command, const std::string& head, double timeout) {
  proc::SpawnOptions so;
  so.own_process_group = true;
  if (auto why = proc::spawn("/bin/sh", {"/bin/sh", "-c", command}, so, ch_); !why.empty()) return why;
  buf_.clear();
  return send(head, timeout);
}

std::string LineChild::send(const std::string& s, double timeout) {
  // Written in pieces of at most PIPE_BUF bytes when the pipe has room, while the program's answers
  // are read into buf_ as they come: a program that answers each line as it reads it fills its
  // output pipe during a large batch, and would wait for us while we wait for it. The timeout
  // runs from the last byte that moved either way.
  const auto span = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout));
  auto deadline = Clock::now() + span;
  bool output_open = true;
  for (std::size_t at = 0; at < s.size();) {
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) return fmt::format("timed out: did not read its input for {} s", timeout);
    pollfd pf[2] = {{ch_.to, POLLOUT, 0}, {output_open ? ch_.from : -1, POLLIN, 0}};
    const int pr = ::poll(pf, 2, static_cast<int>(std::ceil(std::min(left, 1e6) * 1000)));
    if (pr < 0 && errno == EINTR) continue;
    if (pr < 0) return ended();
    if (pr == 0) return fmt::format("timed out: did not read its input for {} s", timeout);
    if (pf[1].revents & (POLLIN | POLLHUP | POLLERR)) {
      char tmp[1 << 14];
      const ssize_t r = ::read(ch_.from, tmp, sizeof tmp);
      if (r > 0) {
        buf_.append(tmp, static_cast<std::size_t>(r));
        deadline = Clock::now() + span;
        if (buf_.size() > (std::size_t{1} << 24)) return "unreadable answer: 16 MiB written before reading its input";
      } else if (r == 0 || (errno != EINTR && errno != EAGAIN)) {
        output_open = false;  // its output closed: the write below tells whether it is gone
      }
    }
    if (pf[0].revents & (POLLERR | POLLHUP)) return ended();
    if (pf[0].revents & POLLOUT) {
      const ssize_t w = ::write(ch_.to, s.data() + at, std::min<std::size_t>(PIPE_BUF, s.size() - at));
      if (w < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (w <= 0) return ended();
      at += static_cast<std::size_t>(w);
      deadline = Clock::now() + span;
    }
  }
  return "";
}

std::string LineChild::line(std::string& out, double timeout) {
  auto deadline = Clock::now() + std::chrono::duration<double>(timeout);
  for (;;) {
    const auto nl = buf_.find('\n');
    if (nl != std::string::npos) {
      out = buf_.substr(0, nl);
      buf_.erase(0, nl + 1);
      return "";
    }
    if (buf_.size() > (1u << 16)) return "unreadable answer: a line longer than 65536 bytes";
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) return fmt::format("timed out: no answer for {} s", timeout);
    pollfd pf{ch_.from, POLLIN, 0};
    const int pr = ::poll(&pf, 1, static_cast<int>(std::ceil(std::min(left, 1e6) * 1000)));
    if (pr < 0 && errno == EINTR) continue;
    if (pr == 0) return fmt::format("timed out: no answer for {} s", timeout);
    char tmp[1 << 14];
    const ssize_t r = ::read(ch_.from, tmp, sizeof tmp);
    if (r < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (r <= 0) return ended();
    buf_.append(tmp, static_cast<std::size_t>(r));
  }
}

std::string LineChild::stop(bool kill) {
  if (!running()) return "";
  return proc::end(ch_, kill, true);
}

std::string LineChild::ended() {
  const std::string how = proc::end(ch_, false, true);
  if (how.rfind("killed", 0) == 0) return "crashed (" + how + ")";
  // /bin/sh reports a command killed by signal N as status 128 + N when it did not exec it.
  int code = 0;
  if (std::sscanf(how.c_str(), "exited with status %d", &code) == 1 && code > 128 && code < 128 + NSIG) {
    const char* name = ::strsignal(code - 128);
    return fmt::format("crashed (signal {}{}; the shell's status {})", code - 128,
                       name ? fmt::format(", {}", name) : std::string(), code);
  }
  return "exited early (" + how + ")";
}

}  // namespace rayproof::verify
