#include "methods/exec_kernel.h"

#include "methods/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <span>
#include <thread>
#include <utility>
#include <vector>


namespace rayproof {

namespace {

using Clock = std::chrono::steady_clock;

constexpr std::size_t kMaxAnswerLine = 1 << 16;  // a longer answer line is garbage
constexpr std::size_t kWriteChunk = 1 << 16;     // bytes of case lines formatted ahead
constexpr std::size_t kOneByOne = 32;            // in-flight sets this small are re-run case by case
constexpr std::size_t kStderrTail = 4096;        // bytes of the kernel's stderr kept for messages

struct Shared {
  std::string name, command;
  Precision precision = Precision::float64;
  std::vector<io::Kind> kinds;
  ExecOptions opt;
  std::mutex mu;
  std::vector<KernelFailure> failures;  // since the last take_failures
  std::size_t failure_count = 0;        // in the run
  std::atomic<bool> dropped{false};
};

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

/// One running kernel process: the parent's ends of its three pipes.
struct Child {
  pid_t pid = -1;
  int in = -1, out = -1, err = -1;
  std::string err_tail;

  Child() = default;
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  ~Child() { finish(true); }

  /// Starts `/bin/sh -c command` in its own process group; "" or the reason it could not start.
  std::string start(const std::string& command) {
    proc::SpawnOptions so;
    so.own_process_group = true;
    so.pipe_stderr = true;
    proc::Child c;
    if (auto why = proc::spawn("/bin/sh", {"/bin/sh", "-c", command}, so, c); !why.empty()) return why;
    pid = c.pid, in = c.to, out = c.from, err = c.err;
    for (int fd : {in, out, err}) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
    ::fcntl(in, F_SETPIPE_SZ, 1 << 20);  // fewer wake-ups; the default size works too
    return "";
  }

  void read_stderr() {
    if (err < 0) return;
    char buf[4096];
    while (true) {
      const ssize_t n = ::read(err, buf, sizeof buf);
      if (n > 0) {
        // Passed through to rayproof's stderr (the contract), and the tail kept for failure messages.
        if (::write(2, buf, static_cast<std::size_t>(n)) < 0) {
        }
        err_tail.append(buf, static_cast<std::size_t>(n));
        if (err_tail.size() > 2 * kStderrTail) err_tail.erase(0, err_tail.size() - kStderrTail);
        continue;
      }
      if (n == 0 || (errno != EINTR && errno != EAGAIN && errno != EWOULDBLOCK)) close_fd(err);
      if (n < 0 && errno == EINTR) continue;
      return;
    }
  }

  /// Waits up to `grace` seconds for the process to exit (killing its group after that, or at once
  /// when `kill_now`), reaps it and kills what is left of its group. The wait status, or -1.
  int finish(bool kill_now, double grace = 0) {
    close_fd(in);
    close_fd(out);
    int status = -1;
    if (pid > 0) {
      if (kill_now) ::kill(-pid, SIGKILL), ::kill(pid, SIGKILL);
      const auto deadline = Clock::now() + std::chrono::duration<double>(grace);
      int sleep_us = 100;
      while (true) {
        const pid_t r = ::waitpid(pid, &status, WNOHANG);
        if (r == pid || (r < 0 && errno != EINTR)) break;
        if (r == 0 && Clock::now() >= deadline) {
          ::kill(-pid, SIGKILL), ::kill(pid, SIGKILL);
          while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
          }
          break;
        }
        if (r == 0) {
          read_stderr();
          std::this_thread::sleep_for(std::chrono::microseconds(sleep_us));
          sleep_us = std::min(sleep_us * 2, 10000);
        }
      }
      ::kill(-pid, SIGKILL);  // anything the shell started and left behind
      pid = -1;
    }
    read_stderr();
    close_fd(err);
    return status;
  }

  /// The last lines of the kernel's stderr, for a failure message ("" when it printed none).
  [[nodiscard]] std::string stderr_lines() const {
    std::vector<std::string> lines;
    std::size_t i = 0;
    while (i < err_tail.size()) {
      std::size_t j = err_tail.find('\n', i);
      if (j == std::string::npos) j = err_tail.size();
      std::string l = err_tail.substr(i, j - i);
      while (!l.empty() && (l.back() == '\r' || l.back() == ' ')) l.pop_back();
      if (!l.empty()) lines.push_back(l.size() > 160 ? l.substr(0, 160) + "..." : l);
      i = j + 1;
    }
    if (lines.empty()) return "";
    std::string s;
    for (std::size_t k = lines.size() > 3 ? lines.size() - 3 : 0; k < lines.size(); ++k) s += (s.empty() ? "" : " | ") + lines[k];
    return s;
  }
};

std::string shown(std::string_view s) {
  std::string out;
  for (char c : s.substr(0, 60)) out += (static_cast<unsigned char>(c) < 32 || c == 127) ? '?' : c;
  return s.size() > 60 ? out + "..." : out;
}

std::string seconds_text(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}

std::string status_text(int status) {
  if (status >= 0 && WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const char* name = ::strsignal(sig);
    return "crashed (signal " + std::to_string(sig) + (name ? std::string(", ") + name : std::string()) + ")";
  }
  if (status >= 0 && WIFEXITED(status)) {
    // /bin/sh reports a command killed by signal N as status 128 + N when it did not exec it.
    const int code = WEXITSTATUS(status);
    if (code > 128 && code < 128 + NSIG) {
      const char* name = ::strsignal(code - 128);
      return "crashed (signal " + std::to_string(code - 128) + (name ? std::string(", ") + name : std::string()) +
             "; the shell's status " + std::to_string(code) + ")";
    }
    return "exited early (status " + std::to_string(code) + ")";
  }
  return "exited early";
}

/// What one pass of cases through one fresh kernel gave.
struct Outcome {
  std::size_t answered = 0;    ///< out[0, answered) hold the kernel's answers
  std::size_t sent = 0;        ///< cases of which the kernel was given at least one byte
  std::string failure;         ///< empty when every case was answered
  bool culprit_known = false;  ///< the answer to case `answered` was unreadable: that case is the culprit
};

/// Streams `cases` through a fresh kernel: writes case lines while reading answers, closes the
/// kernel's input after the last case, stops at the first failure.
Outcome stream(const Shared& sh, std::span<const io::Case> cases, std::span<io::CaseResult> out) {
  Outcome o;
  Child ch;
  if (std::string e = ch.start(sh.command); !e.empty()) {
    o.failure = e;
    return o;
  }
  const auto timeout = std::chrono::duration<double>(sh.opt.timeout_seconds);
  auto last_progress = Clock::now();

  std::string wbuf;
  wbuf.reserve(kWriteChunk + 1024);
  std::size_t woff = 0, formatted = 0;
  std::vector<std::size_t> starts;  // offset in wbuf of each case formatted into it
  std::size_t first_in_buf = 0;     // index of the case at starts[0]

  std::string rbuf;
  std::size_t rscan = 0;  // rbuf[0, rscan) holds no newline
  bool first_line = true, writing = true;

  auto fail = [&](std::string what) { o.failure = std::move(what); };

  while (o.answered < cases.size() && o.failure.empty()) {
    // Refill the write buffer.
    if (writing && woff == wbuf.size()) {
      wbuf.clear(), starts.clear(), woff = 0;
      first_in_buf = formatted;
      while (formatted < cases.size() && wbuf.size() < kWriteChunk) {
        starts.push_back(wbuf.size());
        io::append_case_line(wbuf, cases[formatted++]);
      }
      if (wbuf.empty()) {
        close_fd(ch.in);  // every case written: end of input
        writing = false;
      }
    }
    pollfd fds[3];
    nfds_t n = 0;
    int idx_in = -1, idx_out = -1, idx_err = -1;
    if (writing && ch.in >= 0) idx_in = int(n), fds[n++] = {ch.in, POLLOUT, 0};
    if (ch.out >= 0) idx_out = int(n), fds[n++] = {ch.out, POLLIN, 0};
    if (ch.err >= 0) idx_err = int(n), fds[n++] = {ch.err, POLLIN, 0};
    if (ch.out < 0) break;  // end of the kernel's output before every answer: handled below
    const double left = std::chrono::duration<double>(timeout - (Clock::now() - last_progress)).count();
    const int ms = left <= 0 ? 0 : int(std::ceil(std::min(left, 1e6) * 1000));
    const int pr = ::poll(fds, n, ms);
    if (pr < 0) {
      if (errno == EINTR) continue;
      fail(std::string("poll: ") + std::strerror(errno));
      break;
    }
    if (pr == 0) {
      fail("timed out: no answer for " + seconds_text(sh.opt.timeout_seconds) + " s");
      break;
    }
    if (idx_err >= 0 && fds[idx_err].revents) ch.read_stderr();
    if (idx_in >= 0 && fds[idx_in].revents) {
      const ssize_t w = ::write(ch.in, wbuf.data() + woff, wbuf.size() - woff);
      if (w > 0) {
        woff += static_cast<std::size_t>(w);
        last_progress = Clock::now();
        while (o.sent < formatted && (o.sent < first_in_buf || starts[o.sent - first_in_buf] < woff)) ++o.sent;
      } else if (w < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
        // EPIPE: the kernel closed its input (exited); read what it answered, then judge.
        close_fd(ch.in);
        writing = false;
      }
    }
    if (idx_out >= 0 && fds[idx_out].revents) {
      char buf[1 << 16];
      const ssize_t r = ::read(ch.out, buf, sizeof buf);
      if (r == 0 || (r < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
        close_fd(ch.out);
      } else if (r > 0) {
        last_progress = Clock::now();
        rbuf.append(buf, static_cast<std::size_t>(r));
        std::size_t begin = 0;
        while (o.answered < cases.size()) {
          const std::size_t nl = rbuf.find('\n', std::max(begin, rscan));
          if (nl == std::string::npos) break;
          const std::string_view line(rbuf.data() + begin, nl - begin);
          begin = nl + 1;
          if (first_line) {
            first_line = false;
            if (line.substr(0, 16) == "rayproof-kernel ") continue;  // its declaration
          }
          auto a = io::parse_answer(line);
          if (!a) {
            o.culprit_known = true;
            fail("unreadable answer '" + shown(line) + "'");
            break;
          }
          if (!io::answer_fits(cases[o.answered].kind, *a)) {  // a pair's answer to a ray case, or the reverse
            o.culprit_known = true;
            fail("answer '" + shown(line) + "' is not an answer to a " + std::string(io::to_string(cases[o.answered].kind)) +
                 " case");
            break;
          }
          if (cases[o.answered].kind == io::Kind::tritri) a->pair = true;  // written `hit`, `miss` or the class alone
          out[o.answered++] = *a;
        }
        rbuf.erase(0, begin);
        rscan = rbuf.size();
        if (o.failure.empty() && o.answered < cases.size() && rbuf.size() > kMaxAnswerLine) {
          o.culprit_known = true;
          fail("unreadable answer: a line longer than " + std::to_string(kMaxAnswerLine) + " bytes");
        }
      }
    }
  }
  if (o.answered < cases.size() && o.failure.empty()) {
    // The kernel's output ended early: its exit status says why.
    if (!rbuf.empty()) {
      o.culprit_known = true;
      o.failure = "unreadable answer '" + shown(rbuf) + "' (no end of line, then its output ended)";
      ch.finish(true);
    } else {
      o.failure = status_text(ch.finish(false, std::min(1.0, sh.opt.timeout_seconds)));
    }
  } else if (o.failure.empty()) {
    ch.finish(false, 0.2);  // every answer is in: let it exit on end of input, else kill it
  } else {
    ch.finish(true);
  }
  if (!o.failure.empty()) {
    o.sent = std::max(o.sent, o.answered + 1);
    if (const std::string e = ch.stderr_lines(); !e.empty()) o.failure += "; its stderr ended: " + e;
  }
  return o;
}

void set_error(std::span<io::CaseResult> out) {
  for (auto& r : out) r = io::CaseResult{};  // Contact::error, the answer of a kernel failure
}

/// Records a failure; true when the kernel is dropped by it (or was already).
void record(Shared& sh, const io::Case& c, const std::string& what) {
  std::lock_guard<std::mutex> lock(sh.mu);
  if (sh.dropped) return;
  sh.failures.push_back({what, c});
  if (++sh.failure_count >= sh.opt.max_failures) {
    sh.dropped = true;
    std::fprintf(stderr,
                 "rayproof: kernel %s failed %zu times: dropped from the run; its remaining cases count as kernel "
                 "failures\n",
                 sh.name.c_str(), sh.failure_count);
  }
}

std::size_t answer_all(Shared& sh, std::span<const io::Case> cases, std::span<io::CaseResult> out);

/// Pins a failure seen while `cases` were in flight on the case(s) that cause it. The number of
/// failures recorded.
std::size_t locate(Shared& sh, std::span<const io::Case> cases, std::span<io::CaseResult> out, const std::string& what) {
  if (cases.size() == 1) {
    record(sh, cases[0], what);
    set_error(out);
    return 1;
  }
  std::size_t found = 0;
  if (cases.size() <= kOneByOne) {
    for (std::size_t i = 0; i < cases.size(); ++i) {
      if (sh.dropped) {
        set_error(out.subspan(i));
        return found;
      }
      const Outcome o = stream(sh, cases.subspan(i, 1), out.subspan(i, 1));
      if (!o.failure.empty()) {
        record(sh, cases[i], o.failure);
        out[i] = io::CaseResult{};
        ++found;
      }
    }
  } else {
    const std::size_t half = cases.size() / 2;
    found += answer_all(sh, cases.first(half), out.first(half));
    found += answer_all(sh, cases.subspan(half), out.subspan(half));
  }
  if (found == 0 && !sh.dropped)
    record(sh, cases[0],
           what + " (did not happen again when the " + std::to_string(cases.size()) +
               " cases in flight were re-run in fresh kernels; the first of them is shown)");
  return found;
}

/// Answers every case, restarting the kernel after each failure. The number of failures recorded.
std::size_t answer_all(Shared& sh, std::span<const io::Case> cases, std::span<io::CaseResult> out) {
  std::size_t pos = 0, found = 0;
  while (pos < cases.size()) {
    if (sh.dropped) {
      set_error(out.subspan(pos));
      return found;
    }
    const Outcome o = stream(sh, cases.subspan(pos), out.subspan(pos));
    if (o.failure.empty()) break;
    const std::size_t a = pos + o.answered;
    if (o.culprit_known) {
      record(sh, cases[a], o.failure);
      out[a] = io::CaseResult{};
      ++found;
      pos = a + 1;
      continue;
    }
    const std::size_t end = std::min(cases.size(), pos + o.sent);
    found += locate(sh, cases.subspan(a, end - a), out.subspan(a, end - a), o.failure);
    pos = end;
  }
  return found;
}

void classify_batch(Shared& sh, std::span<const io::Case> in, std::span<io::CaseResult> out) {
  // Only the declared kinds are sent; float kernels see float-rounded inputs whatever the caller did.
  std::vector<io::Case> sent;
  std::vector<std::size_t> where;
  const bool f32 = sh.precision == Precision::float32;
  bool all_plain = !f32;
  for (const auto& c : in)
    if (std::find(sh.kinds.begin(), sh.kinds.end(), c.kind) == sh.kinds.end()) all_plain = false;
  if (all_plain) {
    answer_all(sh, in, out);
    return;
  }
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (std::find(sh.kinds.begin(), sh.kinds.end(), in[i].kind) == sh.kinds.end()) {
      out[i] = io::CaseResult{};
      continue;
    }
    sent.push_back(f32 ? io::round_to_float(in[i]) : in[i]);
    where.push_back(i);
  }
  std::vector<io::CaseResult> got(sent.size());
  answer_all(sh, sent, got);
  for (std::size_t k = 0; k < where.size(); ++k) out[where[k]] = got[k];
}

bool valid_name(std::string_view s) {
  if (s.empty() || s.size() > 64) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == '+')) return false;
  return true;
}

/// Reads `PRECISION KIND[,KIND...]` into sh; "" or what is wrong.
std::string parse_declaration(std::string_view precision, std::string_view kinds, Shared& sh) {
  if (precision == "float") sh.precision = Precision::float32;
  else if (precision == "double") sh.precision = Precision::float64;
  else return "precision '" + shown(precision) + "' is neither float nor double";
  sh.kinds.clear();
  std::size_t i = 0;
  while (i <= kinds.size()) {
    std::size_t j = kinds.find(',', i);
    if (j == std::string_view::npos) j = kinds.size();
    const auto k = io::kind_from_string(kinds.substr(i, j - i));
    if (!k) return "kind '" + shown(kinds.substr(i, j - i)) + "' is not one of plane, sphere, ellipsoid, triangle, box, disk, tritri";
    if (std::find(sh.kinds.begin(), sh.kinds.end(), *k) == sh.kinds.end()) sh.kinds.push_back(*k);
    i = j + 1;
  }
  return "";
}

/// Starts the kernel with its input closed and reads its declaration line.
std::string read_declaration(Shared& sh) {
  Child ch;
  if (std::string e = ch.start(sh.command); !e.empty()) return e;
  close_fd(ch.in);
  std::string line;
  const auto deadline = Clock::now() + std::chrono::duration<double>(sh.opt.timeout_seconds);
  bool done = false;
  while (!done && ch.out >= 0) {
    const auto left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) break;
    pollfd fds[2] = {{ch.out, POLLIN, 0}, {ch.err, POLLIN, 0}};
    const int pr = ::poll(fds, ch.err >= 0 ? 2 : 1, int(std::ceil(left * 1000)));
    if (pr < 0 && errno == EINTR) continue;
    if (pr <= 0) break;
    if (ch.err >= 0 && fds[1].revents) ch.read_stderr();
    if (fds[0].revents) {
      char buf[4096];
      const ssize_t r = ::read(ch.out, buf, sizeof buf);
      if (r > 0) {
        line.append(buf, static_cast<std::size_t>(r));
        const auto nl = line.find('\n');
        if (nl != std::string::npos) line.resize(nl), done = true;
        else if (line.size() > 4096) done = true;
      } else if (r == 0 || (errno != EAGAIN && errno != EINTR)) {
        close_fd(ch.out);
      }
    }
  }
  const int status = ch.finish(true);
  (void)status;
  std::string err = ch.stderr_lines();
  err = err.empty() ? "" : "; its stderr ended: " + err;
  const std::string how = " (declare it with " + sh.name + ":PRECISION:KINDS=COMMAND, or print 'rayproof-kernel 1 PRECISION KIND[,KIND...]' first)";
  if (!done) return "kernel '" + sh.command + "' printed no declaration line" + how + err;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  std::vector<std::string_view> f;
  std::string_view rest = line;
  while (!rest.empty()) {
    const auto b = rest.find_first_not_of(" \t");
    if (b == std::string_view::npos) break;
    rest.remove_prefix(b);
    const auto e = rest.find_first_of(" \t");
    f.push_back(rest.substr(0, e));
    rest.remove_prefix(e == std::string_view::npos ? rest.size() : e);
  }
  if (f.size() != 4 || f[0] != "rayproof-kernel")
    return "kernel '" + sh.command + "' began with '" + shown(line) + "', not a declaration" + how + err;
  if (f[1] != "1") return "kernel '" + sh.command + "' speaks protocol version " + shown(f[1]) + "; this rayproof speaks 1";
  if (std::string e = parse_declaration(f[2], f[3], sh); !e.empty()) return "kernel '" + sh.command + "' declaration: " + e;
  return "";
}

}  // namespace

std::variant<Method, std::string> make_exec_method(std::string_view spec, const ExecOptions& opt) {
  static std::once_flag sigpipe;
  std::call_once(sigpipe, [] { ::signal(SIGPIPE, SIG_IGN); });

  const auto eq = spec.find('=');
  if (eq == std::string_view::npos) return std::string("'").append(spec).append("' is not NAME=COMMAND or NAME:PRECISION:KINDS=COMMAND");
  auto sh = std::make_shared<Shared>();
  sh->command = std::string(spec.substr(eq + 1));
  sh->opt = opt;
  if (!(opt.timeout_seconds > 0) || !std::isfinite(opt.timeout_seconds))
    return "the kernel timeout must be a positive number of seconds";
  if (sh->command.find_first_not_of(" \t") == std::string::npos) return std::string("'").append(spec).append("' has no command after '='");
  const std::string_view head = spec.substr(0, eq);
  const auto c1 = head.find(':');
  sh->name = std::string(head.substr(0, c1));
  if (!valid_name(sh->name))
    return "kernel name '" + shown(sh->name) + "' must be 1 to 64 letters, digits or _ - . +";
  if (c1 != std::string_view::npos) {
    const auto c2 = head.find(':', c1 + 1);
    if (c2 == std::string_view::npos) return std::string("'").append(head).append("' is not NAME:PRECISION:KINDS");
    if (std::string e = parse_declaration(head.substr(c1 + 1, c2 - c1 - 1), head.substr(c2 + 1), *sh); !e.empty())
      return "--exec " + sh->name + ": " + e;
  } else if (std::string e = read_declaration(*sh); !e.empty()) {
    return "--exec " + sh->name + ": " + e;
  }

  Method m;
  m.name = sh->name;
  m.summary = "your kernel over the line protocol: " + sh->command;
  m.precision = sh->precision;
  m.kinds = sh->kinds;
  m.classify_batch = [sh](std::span<const io::Case> in, std::span<io::CaseResult> out) { classify_batch(*sh, in, out); };
  m.classify = [sh](const io::Case& c) {
    io::CaseResult r;
    classify_batch(*sh, std::span<const io::Case>(&c, 1), std::span<io::CaseResult>(&r, 1));
    return r;
  };
  m.take_failures = [sh] {
    std::lock_guard<std::mutex> lock(sh->mu);
    return std::exchange(sh->failures, {});
  };
  return m;
}

}  // namespace rayproof
