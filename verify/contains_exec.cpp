// The --contains line protocol: a program fed the mesh once and batches of points
// (verify/contains_exec.h; docs/check.md, "Inside/outside").
#include "verify/contains_exec.h"

#include <fmt/core.h>

#include <cerrno>
#include <cstdlib>
#include <functional>
#include <limits>

#include "verify/line_child.h"

namespace rayproof::verify {

namespace {

constexpr std::size_t kMaxFailures = 20;

std::string mesh_head(const char* protocol, const ContainsMesh& mesh) {
  std::string head = fmt::format("{} 1\nvertices {}\n", protocol, mesh.vertices.size());
  for (const auto& v : mesh.vertices)
    head += fmt::format("{} {} {}\n", protocol_number(v.x), protocol_number(v.y), protocol_number(v.z));
  head += fmt::format("triangles {}\n", mesh.triangles.size());
  for (const auto& f : mesh.triangles) head += fmt::format("{} {} {}\n", f[0], f[1], f[2]);
  return head;
}

}  // namespace

bool parse_contains_answer(const std::string& line, long long& side) {
  const char* p = line.c_str();
  char* end = nullptr;
  errno = 0;
  side = std::strtoll(p, &end, 10);
  if (end == p || errno == ERANGE) return false;
  for (p = end; *p; ++p)
    if (*p != ' ' && *p != '\t' && *p != '\r') return false;
  return true;
}

ExecPointsRun run_exec_points(const std::string& command, const char* protocol, const ContainsMesh& mesh,
                              const ContainsPoints& points, const ExecContainsOptions& opt,
                              const std::function<bool(const std::string&, std::size_t)>& answer) {
  ignore_sigpipe();
  ExecPointsRun run;
  const std::size_t n = points.points.size();
  run.failed.assign(n, false);
  const std::string head = mesh_head(protocol, mesh);
  LineChild child;
  const std::size_t batch = std::max<std::size_t>(opt.batch, 1);
  std::size_t at = 0, failures = 0;
  while (at < n) {
    if (failures >= kMaxFailures) {
      for (std::size_t i = at; i < n; ++i) run.failed[i] = true;
      run.events.push_back(fmt::format("dropped after {} failures: points {}..{} not sent ({} points counted as "
                                       "failures)", failures, at, n - 1, n - at));
      break;
    }
    const std::uint8_t set = points.set[at];
    const std::size_t cap = points.names[set] == "invalid" ? 1 : batch;
    std::size_t end = at;
    while (end < n && end - at < cap && points.set[end] == set) ++end;
    auto fail_rest = [&](std::size_t from, const std::string& why) {
      ++failures;
      for (std::size_t i = from; i < end; ++i) run.failed[i] = true;
      const std::string which =
          end - from == 1 ? fmt::format("point {}", from) : fmt::format("points {}..{}", from, end - 1);
      run.events.push_back(fmt::format("{} on {} (set {}; {} points counted as failures)", why, which,
                                       points.names[set], end - from));
      child.stop(true);
    };
    std::string why;
    if (!child.running()) {
      ++run.starts;
      why = child.start(command, head, opt.timeout_seconds);
    }
    if (why.empty()) {
      std::string msg = fmt::format("points {}\n", end - at);
      for (std::size_t i = at; i < end; ++i) {
        const Vec3<double>& p = points.points[i];
        msg += fmt::format("{} {} {}\n", protocol_number(p.x), protocol_number(p.y), protocol_number(p.z));
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
      if (!answer(l, i)) {
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
  return run;
}

ExecContainsRun run_exec_contains(const std::string& command, const ContainsMesh& mesh, const ContainsPoints& points,
                                  const ExecContainsOptions& opt) {
  ExecContainsRun run;
  run.answers.assign(points.points.size(), ContainsAnswer{});
  ExecPointsRun r = run_exec_points(command, "rayproof-contains", mesh, points, opt,
                                    [&](const std::string& line, std::size_t i) {
                                      long long side = 0;
                                      if (!parse_contains_answer(line, side)) return false;
                                      // Beyond int32: garbage all the same.
                                      constexpr long long lo = std::numeric_limits<std::int32_t>::min(),
                                                          hi = std::numeric_limits<std::int32_t>::max();
                                      run.answers[i].side = side <= lo || side > hi ? ContainsAnswer::kNotAnInteger
                                                                                    : static_cast<std::int32_t>(side);
                                      return true;
                                    });
  for (std::size_t i = 0; i < run.answers.size(); ++i) run.answers[i].failed = r.failed[i];
  run.events = std::move(r.events);
  run.starts = r.starts;
  return run;
}

bool parse_distance_answer(const std::string& line, double& d) {
  const char* p = line.c_str();
  char* end = nullptr;
  d = std::strtod(p, &end);
  if (end == p) return false;
  for (p = end; *p; ++p)
    if (*p != ' ' && *p != '\t' && *p != '\r') return false;
  return true;
}

ExecDistanceRun run_exec_distance(const std::string& command, const ContainsMesh& mesh, const ContainsPoints& points,
                                  const ExecContainsOptions& opt) {
  ExecDistanceRun run;
  run.answers.assign(points.points.size(), DistanceAnswer{});
  ExecPointsRun r = run_exec_points(command, "rayproof-distance", mesh, points, opt,
                                    [&](const std::string& line, std::size_t i) {
                                      return parse_distance_answer(line, run.answers[i].distance);
                                    });
  for (std::size_t i = 0; i < run.answers.size(); ++i) run.answers[i].failed = r.failed[i];
  run.events = std::move(r.events);
  run.starts = r.starts;
  return run;
}

}  // namespace rayproof::verify
