// The --caster line protocol: a caster program fed the mesh once and batches of rays
// (verify/caster_exec.h; docs/check.md, "Whole casters").
#include "verify/caster_exec.h"

#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <fmt/core.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "methods/child_process.h"

namespace rayproof::verify {

namespace {

using Clock = proc::Clock;
constexpr std::size_t kMaxFailures = 20;

std::string num(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return fmt::format("{}", x);
}

std::string printable(const std::string& s) {
  std::string out;
  for (char c : s.substr(0, 60)) out += (static_cast<unsigned char>(c) < 32 || c == 127) ? '?' : c;
  return s.size() > 60 ? out + "..." : out;
}

/// One running caster: the child, its unread output.
class Running {
 public:
  ~Running() { stop(true); }
  std::string start(const std::string& command, const CasterMesh& mesh, double timeout) {
    proc::SpawnOptions so;
    so.own_process_group = true;
    if (auto why = proc::spawn("/bin/sh", {"/bin/sh", "-c", command}, so, ch_); !why.empty()) return why;
    buf_.clear();
    std::string head = fmt::format("rayproof-caster 1\nvertices {}\n", mesh.vertices.size());
    for (const auto& v : mesh.vertices) head += fmt::format("{} {} {}\n", num(v.x), num(v.y), num(v.z));
    head += fmt::format("triangles {}\n", mesh.triangles.size());
    for (const auto& f : mesh.triangles) head += fmt::format("{} {} {}\n", f[0], f[1], f[2]);
    return send(head, timeout);
  }
  [[nodiscard]] bool running() const { return ch_.pid > 0; }
  /// "" when written; else how the caster failed.
  std::string send(const std::string& s, double timeout) {
    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout));
    switch (proc::write_all(ch_.to, s.data(), s.size(), deadline)) {
      case proc::Io::ok: return "";
      case proc::Io::timeout: return fmt::format("timed out: did not read its input for {} s", timeout);
      default: return ended();
    }
  }
  /// One answer line; "" and the line, or how the caster failed.
  std::string line(std::string& out, double timeout) {
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
  std::string stop(bool kill) {
    if (!running()) return "";
    return proc::end(ch_, kill, true);
  }

 private:
  std::string ended() {
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
  proc::Child ch_;
  std::string buf_;
};

}  // namespace

bool parse_caster_answer(const std::string& line, double& t, long long& triangle) {
  const char* p = line.c_str();
  char* end = nullptr;
  t = std::strtod(p, &end);
  if (end == p) return false;
  p = end;
  errno = 0;
  triangle = std::strtoll(p, &end, 10);
  if (end == p || errno == ERANGE) return false;
  for (p = end; *p; ++p)
    if (*p != ' ' && *p != '\t' && *p != '\r') return false;
  return true;
}

ExecCasterRun run_exec_caster(const std::string& command, const CasterMesh& mesh, const CasterRays& rays,
                              const ExecCasterOptions& opt) {
  static std::once_flag sigpipe;
  std::call_once(sigpipe, [] { ::signal(SIGPIPE, SIG_IGN); });  // a caster that dies while we write must not kill us
  ExecCasterRun run;
  const std::size_t n = rays.rays.size();
  run.answers.assign(n, CasterAnswer{});
  Running child;
  const std::size_t batch = std::max<std::size_t>(opt.batch, 1);
  std::size_t at = 0, failures = 0;
  while (at < n) {
    if (failures >= kMaxFailures) {  // as --exec kernels: dropped after this many failures
      for (std::size_t i = at; i < n; ++i) run.answers[i].failed = true;
      run.events.push_back(fmt::format("dropped after {} failures: rays {}..{} not sent ({} rays counted as failures)",
                                       failures, at, n - 1, n - at));
      break;
    }
    // A batch: up to `batch` rays of one set (one ray in the invalid set).
    const std::uint8_t set = rays.set[at];
    const std::size_t cap = rays.names[set] == "invalid" ? 1 : batch;
    std::size_t end = at;
    while (end < n && end - at < cap && rays.set[end] == set) ++end;
    auto fail_rest = [&](std::size_t from, const std::string& why) {
      ++failures;
      for (std::size_t i = from; i < end; ++i) run.answers[i].failed = true;
      const std::string rays_text = end - from == 1 ? fmt::format("ray {}", from) : fmt::format("rays {}..{}", from, end - 1);
      run.events.push_back(fmt::format("{} on {} (set {}; {} rays counted as failures)", why, rays_text,
                                       rays.names[set], end - from));
      child.stop(true);
    };
    std::string why;
    if (!child.running()) {
      ++run.starts;
      why = child.start(command, mesh, opt.timeout_seconds);
    }
    if (why.empty()) {
      std::string msg = fmt::format("rays {}\n", end - at);
      for (std::size_t i = at; i < end; ++i) {
        const Ray<double>& r = rays.rays[i];
        msg += fmt::format("{} {} {} {} {} {}\n", num(r.o.x), num(r.o.y), num(r.o.z), num(r.d.x), num(r.d.y), num(r.d.z));
      }
      why = child.send(msg, opt.timeout_seconds);
    }
    if (!why.empty()) {
      fail_rest(at, why);
      at = end;
      continue;
    }
    for (std::size_t i = at; i < end; ++i) {
      std::string l;
      if (std::string e = child.line(l, opt.timeout_seconds); !e.empty()) {
        fail_rest(i, e);
        break;
      }
      double t;
      long long tri;
      if (!parse_caster_answer(l, t, tri)) {
        fail_rest(i, "unreadable answer '" + printable(l) + "'");
        break;
      }
      run.answers[i].t = t;
      run.answers[i].triangle = tri;
    }
    at = end;
  }
  if (child.running()) {
    (void)child.send("end\n", 1.0);
    child.stop(true);
  }
  return run;
}

}  // namespace rayproof::verify
