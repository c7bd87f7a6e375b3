#include "methods/glsl_kernel.h"

#include "methods/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <fmt/core.h>
#include <memory>
#include <mutex>
#include <vector>

#include "methods/glsl_source.h"
#include "methods/plugin_kernel.h"
#include "rayproof/plugin.h"


namespace rayproof {

namespace {

/// Frames between rayproof and `rayproof glsl-host` (both sides of this file):
///   hello (child):    u32 status (0 ready, 1 failed), u32 length, text
///                     ready: "kinds\tK,K..\ndevice\tDESCRIPTION\nsubnormals\tTEXT\n"; failed: the message
///   request (parent): u32 kind, u32 n, n * kInReals reals; kind kStop ends the child
///   answer (child):   u32 status (0), n * kOutReals reals (code, t, b1, b2); or u32 1, u32 length, text
///                     reals: float for a float shader, double for a double one
///                     (the device was lost, ...), after which the child exits
constexpr std::uint32_t kStop = 0xffffffffu;
constexpr std::size_t kChunk = 65536;   // cases per request (Runner::max_cases)
constexpr std::size_t kMaxKept = 10000;  // failures kept between two takes
constexpr double kStartSeconds = 60;     // compile and open the device

using Clock = proc::Clock;
using proc::Io;
using proc::read_all;
using proc::write_all;
using Child = proc::Child;

/// The child's exit, once it has ended (or been killed): "exited with status 3", "killed by signal 11 (...)".
std::string reap(Child& ch, bool kill_first) { return proc::end(ch, kill_first); }

struct State {
  std::string name, file, host;
  Precision precision = Precision::float32;
  GlslOptions opt;
  std::mutex mutex;
  Child child;
  std::string device, subnormals;
  std::vector<io::Kind> kinds;
  std::string dropped;  ///< why the kernel cannot run any more (a restart failed)
  std::vector<KernelFailure> failures;
  std::vector<double> out;
  std::vector<unsigned char> inbuf, outbuf;  ///< the frames' reals (float or double)

  ~State() {
    if (child.pid > 0) {
      const std::array<std::uint32_t, 2> stop{kStop, 0};
      (void)write_all(child.to, stop.data(), sizeof stop, Clock::now() + std::chrono::seconds(1));
      ::close(child.to);
      child.to = -1;
      // A child still running a hung dispatch does not read the stop: give it a moment, then kill it.
      const auto until = Clock::now() + std::chrono::seconds(2);
      int status = 0;
      while (::waitpid(child.pid, &status, WNOHANG) == 0 && Clock::now() < until) ::usleep(2000);
      if (::waitpid(child.pid, &status, WNOHANG) == 0) (void)reap(child, true);
      else {
        if (child.from >= 0) ::close(child.from);
        child.pid = -1;
      }
    }
  }

  void fail(const io::Case& c, const std::string& what) {
    if (failures.size() < kMaxKept) failures.push_back({what, c});
  }

  /// Starts the child and reads its hello: empty, or why it could not start.
  std::string start() {
    static std::once_flag sigpipe;
    std::call_once(sigpipe, [] { ::signal(SIGPIPE, SIG_IGN); });
    std::vector<std::string> args{host, "glsl-host", "--file", file, "--precision",
                                  precision == Precision::float32 ? "float" : "double", "--device",
                                  std::to_string(opt.device)};
    if (opt.no_contraction) args.push_back("--no-contraction");
    if (auto why = proc::spawn(host, args, {}, child); !why.empty()) return why + " (the glsl-host of the shader)";
    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(std::max(kStartSeconds, opt.timeout_seconds)));
    std::array<std::uint32_t, 2> head{};
    if (Io r = read_all(child.from, head.data(), sizeof head, deadline); r != Io::ok) {
      const std::string how = reap(child, true);
      return r == Io::timeout ? fmt::format("the shader process did not start within {} s", kStartSeconds)
                              : "the shader process ended before it said whether the shader compiled (" + how + ")";
    }
    std::string text(head[1], '\0');
    if (head[1] > (1u << 24) || read_all(child.from, text.data(), text.size(), deadline) != Io::ok) {
      (void)reap(child, true);
      return "the shader process sent a garbled hello";
    }
    if (head[0] != 0) {
      (void)reap(child, true);
      return text;
    }
    kinds.clear();
    std::size_t pos = 0;
    while (pos < text.size()) {
      const std::size_t end = std::min(text.find('\n', pos), text.size());
      const std::string line = text.substr(pos, end - pos);
      pos = end + 1;
      const std::size_t tab = line.find('\t');
      if (tab == std::string::npos) continue;
      const std::string key = line.substr(0, tab), value = line.substr(tab + 1);
      if (key == "device") device = value;
      else if (key == "subnormals") subnormals = value;
      else if (key == "kinds")
        for (std::size_t a = 0; a <= value.size();) {
          const std::size_t b = std::min(value.find(',', a), value.size());
          if (auto k = io::kind_from_string(value.substr(a, b - a))) kinds.push_back(*k);
          a = b + 1;
        }
    }
    return {};
  }

  /// One request of n <= kChunk cases of kind k, `idx` into the batch; answers into `res`.
  void run_chunk(io::Kind k, std::span<const io::Case> cases, const std::vector<std::size_t>& idx,
                 std::span<io::CaseResult> res) {
    const std::size_t n = idx.size();
    auto fail_all = [&](const std::string& what) {
      for (std::size_t i : idx) {
        res[i] = {Contact::error};
        fail(cases[i], what);
      }
    };
    if (!dropped.empty()) return fail_all(dropped);
    if (child.pid <= 0) {
      if (auto why = start(); !why.empty()) {
        dropped = "not run: the shader process could not be restarted: " + why;
        return fail_all(dropped);
      }
    }
    std::array<std::uint32_t, 2> head{static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(n)};
    const bool dbl = precision == Precision::float64;
    const std::size_t real = dbl ? sizeof(double) : sizeof(float);
    inbuf.assign(n * glsl::kInReals * real, 0);
    if (dbl) {
      auto* p = reinterpret_cast<double*>(inbuf.data());
      for (std::size_t j = 0; j < n; ++j) std::copy(cases[idx[j]].v.begin(), cases[idx[j]].v.end(), p + j * glsl::kInReals);
    } else {
      auto* p = reinterpret_cast<float*>(inbuf.data());
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t f = 0; f < 15; ++f) p[j * glsl::kInReals + f] = static_cast<float>(cases[idx[j]].v[f]);
    }
    const auto deadline =
        Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(opt.timeout_seconds));
    Io r = write_all(child.to, head.data(), sizeof head, deadline);
    if (r == Io::ok) r = write_all(child.to, inbuf.data(), inbuf.size(), deadline);
    std::uint32_t status = 0;
    if (r == Io::ok) r = read_all(child.from, &status, sizeof status, deadline);
    if (r == Io::ok && status == 0) {
      outbuf.resize(n * glsl::kOutReals * real);
      r = read_all(child.from, outbuf.data(), outbuf.size(), deadline);
      out.resize(n * glsl::kOutReals);
      if (dbl) std::memcpy(out.data(), outbuf.data(), outbuf.size());
      else
        for (std::size_t i = 0; i < out.size(); ++i) out[i] = reinterpret_cast<const float*>(outbuf.data())[i];
    } else if (r == Io::ok) {
      std::uint32_t len = 0;
      std::string text;
      if (read_all(child.from, &len, sizeof len, deadline) == Io::ok && len < (1u << 20)) {
        text.resize(len);
        (void)read_all(child.from, text.data(), len, deadline);
      }
      (void)reap(child, true);
      return fail_all(fmt::format("{} (in a dispatch of {} cases); the shader process and its device were restarted",
                                  text.empty() ? "the shader process failed" : text, n));
    }
    if (r == Io::timeout) {
      (void)reap(child, true);
      return fail_all(fmt::format("timed out: no answer within {} s for a dispatch of {} cases (one invocation per "
                                  "case; the shader may loop forever); the shader process was ended and restarted",
                                  opt.timeout_seconds, n));
    }
    if (r != Io::ok) {
      const std::string how = reap(child, true);
      return fail_all(fmt::format("the shader process died during a dispatch of {} cases ({})", n, how));
    }
    for (std::size_t j = 0; j < n; ++j) {
      const double* a = out.data() + j * glsl::kOutReals;
      const std::size_t i = idx[j];
      rayproof_answer ans{RAYPROOF_NO_ANSWER, 0, 0.0, 0.0, 0.0, 0.0};
      const int code = a[0] >= -1 && a[0] <= 4 && a[0] == std::floor(a[0]) ? int(a[0]) : -1;
      if (code == glsl::kMiss) {
        ans.cls = RAYPROOF_COARSE_MISS;
      } else if (code == glsl::kHit || code == glsl::kHitT || code == glsl::kHitTB) {
        ans.cls = RAYPROOF_COARSE_HIT;
        if (code != glsl::kHit) ans.has |= RAYPROOF_HAS_T, ans.t = a[1];
        if (code == glsl::kHitTB) ans.has |= RAYPROOF_HAS_B, ans.b1 = a[2], ans.b2 = a[3];
      } else {
        res[i] = {Contact::error};
        fail(cases[i], fmt::format("answer outside the vocabulary: {} returned {}, not RAYPROOF_MISS, RAYPROOF_HIT, "
                                   "RAYPROOF_HIT_T or RAYPROOF_HIT_TB", glsl::function_name(k), io::format_double(a[0])));
        continue;
      }
      auto got = plugin_answer_to_result(k, ans);
      if (auto* ok = std::get_if<io::CaseResult>(&got)) {
        res[i] = *ok;
      } else {
        res[i] = {Contact::error};
        fail(cases[i], std::get<std::string>(got) + " (RAYPROOF_HIT_TB is for triangles)");
      }
    }
  }

  void classify(std::span<const io::Case> cases, std::span<io::CaseResult> res) {
    std::lock_guard lock(mutex);
    std::array<std::vector<std::size_t>, 6> by_kind;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      if (std::find(kinds.begin(), kinds.end(), cases[i].kind) == kinds.end()) {
        res[i] = {Contact::error};
        continue;
      }
      by_kind[static_cast<std::size_t>(cases[i].kind)].push_back(i);
    }
    for (std::size_t k = 0; k < 6; ++k)
      for (std::size_t a = 0; a < by_kind[k].size(); a += kChunk) {
        const std::size_t b = std::min(by_kind[k].size(), a + kChunk);
        std::vector<std::size_t> idx(by_kind[k].begin() + std::ptrdiff_t(a), by_kind[k].begin() + std::ptrdiff_t(b));
        run_chunk(static_cast<io::Kind>(k), cases, idx, res);
      }
  }
};

}  // namespace

std::variant<Method, std::string> make_glsl_method(const std::string& spec, const GlslOptions& opt) {
  std::string name, file = spec;
  Precision precision = Precision::float32;
  if (const auto eq = spec.find('='); eq != std::string::npos) {
    name = spec.substr(0, eq);
    file = spec.substr(eq + 1);
    if (const auto colon = name.find(':'); colon != std::string::npos) {
      const std::string p = name.substr(colon + 1);
      name = name.substr(0, colon);
      if (p == "double") precision = Precision::float64;
      else if (p != "float")
        return fmt::format("--glsl {}: unknown precision '{}' (NAME:float=FILE or NAME:double=FILE)", spec, p);
    }
  }
  if (file.empty()) return fmt::format("--glsl {}: no FILE (NAME=FILE)", spec);
  if (name.empty()) name = std::filesystem::path(file).stem().string();
  if (name.empty()) return fmt::format("--glsl {}: no NAME (NAME=FILE)", spec);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return fmt::format("--glsl {}: {}: no such file", spec, file);
  if (opt.host.empty()) return fmt::format("--glsl {}: no rayproof executable to host the shader", spec);
  {  // The old rp_ names work for one release, said once per file.
    std::ifstream in(file, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    if (const auto w = glsl::legacy_names_warning(file, text.str()); !w.empty()) fmt::print(stderr, "{}\n", w);
  }

  auto st = std::make_shared<State>();
  st->name = name;
  st->file = std::filesystem::absolute(file, ec).string();
  st->host = opt.host;
  st->precision = precision;
  st->opt = opt;
  if (auto why = st->start(); !why.empty()) return fmt::format("--glsl {}: {}", spec, why);

  Method m;
  m.name = name;
  m.precision = precision;
  m.kinds = st->kinds;
  m.summary = fmt::format("GLSL shader {} ({}{}) on {}", file, precision == Precision::float32 ? "float" : "double",
                          opt.no_contraction ? ", every float operation precise" : "", st->device);
  if (!st->subnormals.empty()) m.summary += "; " + st->subnormals;
  m.classify_batch = [st](std::span<const io::Case> in, std::span<io::CaseResult> out) { st->classify(in, out); };
  m.classify = [st](const io::Case& c) {
    io::CaseResult r;
    st->classify(std::span<const io::Case>(&c, 1), std::span<io::CaseResult>(&r, 1));
    return r;
  };
  m.take_failures = [st] {
    std::lock_guard lock(st->mutex);
    std::vector<KernelFailure> out;
    out.swap(st->failures);
    return out;
  };
  return m;
}

}  // namespace rayproof
