// What the judges of whole functions share (verify/judge_frame.h): the line-protocol batch runner
// over LineChild, the protocols' header and answer lines, exact numbers.
#include "verify/judge_frame.h"

#include <fmt/core.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdlib>

#include "verify/line_child.h"

namespace rayproof::verify {

namespace {
constexpr std::size_t kMaxFailures = 20;  // as --exec kernels: dropped after this many failures
}  // namespace

std::string ratio_text(double judge_seconds, double baseline_seconds) {
  return baseline_seconds > 0 ? fmt::format("{:.2f}x", judge_seconds / baseline_seconds) : std::string("-");
}

std::string exact_number(double x) { return protocol_number(x); }

std::string exact_point(const Vec3<double>& p) {
  return fmt::format("{} {} {}", exact_number(p.x), exact_number(p.y), exact_number(p.z));
}

std::string mesh_protocol_head(std::string_view protocol, std::span<const Vec3<double>> vertices,
                               std::span<const std::array<std::uint32_t, 3>> triangles) {
  std::string head = fmt::format("{} 1\nvertices {}\n", protocol, vertices.size());
  for (const auto& v : vertices) head += exact_point(v) + "\n";
  head += fmt::format("triangles {}\n", triangles.size());
  for (const auto& f : triangles) head += fmt::format("{} {} {}\n", f[0], f[1], f[2]);
  return head;
}

bool parse_fields(const std::string& line, std::string_view kinds, double* doubles, long long* integers) {
  const char* p = line.c_str();
  char* end = nullptr;
  for (const char kind : kinds) {
    if (kind == 'd') {
      *doubles++ = std::strtod(p, &end);
      if (end == p) return false;
    } else {
      errno = 0;
      *integers++ = std::strtoll(p, &end, 10);
      if (end == p || errno == ERANGE) return false;
    }
    p = end;
  }
  for (; *p; ++p)
    if (*p != ' ' && *p != '\t' && *p != '\r') return false;
  return true;
}

LineBatchRun run_line_batches(const std::string& command, const std::string& head, LineItems items,
                              std::span<const std::uint8_t> set, std::span<const std::string> names,
                              const LineBatchOptions& opt, const std::function<void(std::size_t, std::string&)>& write,
                              const std::function<bool(const std::string&, std::size_t)>& read) {
  ignore_sigpipe();  // a program that dies while we write must not kill us
  const auto began = std::chrono::steady_clock::now();
  LineBatchRun run;
  const std::size_t n = set.size();
  run.failed.assign(n, false);
  LineChild child;
  const std::size_t batch = std::max<std::size_t>(opt.batch, 1);
  std::size_t at = 0, failures = 0;
  while (at < n) {
    if (failures >= kMaxFailures) {
      for (std::size_t i = at; i < n; ++i) run.failed[i] = true;
      run.events.push_back(fmt::format("dropped after {} failures: {} {}..{} not sent ({} {} counted as failures)",
                                       failures, items.many, at, n - 1, n - at, items.many));
      break;
    }
    // A batch: up to `batch` items of one set (one item in the invalid set).
    const std::uint8_t s = set[at];
    const std::size_t cap = names[s] == "invalid" ? 1 : batch;
    std::size_t end = at;
    while (end < n && end - at < cap && set[end] == s) ++end;
    auto fail_rest = [&](std::size_t from, const std::string& why) {
      ++failures;
      for (std::size_t i = from; i < end; ++i) run.failed[i] = true;
      const std::string which = end - from == 1 ? fmt::format("{} {}", items.one, from)
                                                : fmt::format("{} {}..{}", items.many, from, end - 1);
      run.events.push_back(
          fmt::format("{} on {} (set {}; {} {} counted as failures)", why, which, names[s], end - from, items.many));
      child.stop(true);
    };
    std::string why;
    if (!child.running()) {
      ++run.starts;
      why = child.start(command, head, opt.timeout_seconds);
    }
    if (why.empty()) {
      std::string msg = fmt::format("{} {}\n", items.many, end - at);
      for (std::size_t i = at; i < end; ++i) write(i, msg);
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
      if (!read(l, i)) {
        fail_rest(i, "unreadable answer '" + printable(l) + "'");
        break;
      }
    }
    at = end;
  }
  if (child.running()) {
    (void)child.send("end\n", 1.0);
    child.stop(true);
  }
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  return run;
}

}  // namespace rayproof::verify
