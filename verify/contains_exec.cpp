// The --contains line protocol: a program fed the mesh once and batches of points
// (verify/contains_exec.h; docs/check.md, "Inside/outside"), run by run_line_batches (judge_frame.h).
#include "verify/contains_exec.h"

#include <functional>
#include <limits>

#include "verify/judge_frame.h"

namespace rayproof::verify {

bool parse_contains_answer(const std::string& line, long long& side) { return parse_fields(line, "i", nullptr, &side); }

namespace {

/// `command` run on every point under the protocol named `protocol`; read(line, i) takes point i's
/// answer line.
LineBatchRun run_on_points(const std::string& command, const char* protocol, const ContainsMesh& mesh,
                           const ContainsPoints& points, const ExecContainsOptions& opt,
                           const std::function<bool(const std::string&, std::size_t)>& read) {
  return run_line_batches(
      command, mesh_protocol_head(protocol, mesh.vertices, mesh.triangles), {"point", "points"}, points.set,
      points.names, opt, [&](std::size_t i, std::string& msg) { msg += exact_point(points.points[i]) + "\n"; }, read);
}

}  // namespace

ExecContainsRun run_exec_contains(const std::string& command, const ContainsMesh& mesh, const ContainsPoints& points,
                                  const ExecContainsOptions& opt) {
  std::vector<ContainsAnswer> answers(points.points.size());
  LineBatchRun r = run_on_points(command, "rayproof-contains", mesh, points, opt, [&](const std::string& line, std::size_t i) {
    long long side = 0;
    if (!parse_contains_answer(line, side)) return false;
    // Beyond int32: garbage all the same.
    constexpr long long lo = std::numeric_limits<std::int32_t>::min(), hi = std::numeric_limits<std::int32_t>::max();
    answers[i].side = side <= lo || side > hi ? ContainsAnswer::kNotAnInteger : static_cast<std::int32_t>(side);
    return true;
  });
  return with_failures(std::move(answers), std::move(r));
}

bool parse_distance_answer(const std::string& line, double& d) { return parse_fields(line, "d", &d, nullptr); }

bool parse_distance_answer(const std::string& line, DistanceAnswer& a) {
  double f[4];
  long long triangle = -1;
  if (parse_fields(line, "d", f, nullptr)) {
    a.distance = f[0];
    return true;
  }
  const bool with_triangle = parse_fields(line, "ddddi", f, &triangle);
  if (!with_triangle && !parse_fields(line, "dddd", f, nullptr)) return false;
  a.distance = f[0];
  a.point = {f[1], f[2], f[3]};
  a.has_point = true;
  a.triangle = triangle;
  a.has_triangle = with_triangle;
  return true;
}

ExecDistanceRun run_exec_distance(const std::string& command, const ContainsMesh& mesh, const ContainsPoints& points,
                                  const ExecContainsOptions& opt) {
  std::vector<DistanceAnswer> answers(points.points.size());
  LineBatchRun r = run_on_points(command, "rayproof-distance", mesh, points, opt, [&](const std::string& line, std::size_t i) {
    return parse_distance_answer(line, answers[i]);
  });
  return with_failures(std::move(answers), std::move(r));
}

}  // namespace rayproof::verify
