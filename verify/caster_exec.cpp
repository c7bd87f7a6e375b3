// The --caster line protocol: a caster program fed the mesh once and batches of rays
// (verify/caster_exec.h; docs/check.md, "Whole casters").
#include "verify/caster_exec.h"

#include <fmt/core.h>

#include <cerrno>
#include <cstdlib>

#include "verify/line_child.h"

namespace rayproof::verify {

namespace {

constexpr std::size_t kMaxFailures = 20;

std::string num(double x) { return protocol_number(x); }

/// One running caster: the line child, fed the mesh first.
class Running : public LineChild {
 public:
  std::string start(const std::string& command, const CasterMesh& mesh, double timeout) {
    std::string head = fmt::format("rayproof-caster 1\nvertices {}\n", mesh.vertices.size());
    for (const auto& v : mesh.vertices) head += fmt::format("{} {} {}\n", num(v.x), num(v.y), num(v.z));
    head += fmt::format("triangles {}\n", mesh.triangles.size());
    for (const auto& f : mesh.triangles) head += fmt::format("{} {} {}\n", f[0], f[1], f[2]);
    return LineChild::start(command, head, timeout);
  }
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
  ignore_sigpipe();  // a caster that dies while we write must not kill us
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
