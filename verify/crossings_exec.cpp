// The --crossings line protocol (verify/crossings_exec.h; docs/check.md, "All hits").
#include "verify/crossings_exec.h"

#include <cerrno>
#include <cstdlib>

namespace rayproof::verify {

bool parse_crossings_answer(const std::string& line, std::vector<CrossingHit>& hits) {
  hits.clear();
  const char* p = line.c_str();
  char* end = nullptr;
  errno = 0;
  const long long k = std::strtoll(p, &end, 10);
  if (end == p || errno == ERANGE || k < 0 || k > 1000000) return false;
  p = end;
  for (long long i = 0; i < k; ++i) {
    CrossingHit h;
    h.t = std::strtod(p, &end);
    if (end == p) return false;
    p = end;
    errno = 0;
    h.triangle = std::strtoll(p, &end, 10);
    if (end == p || errno == ERANGE) return false;
    p = end;
    hits.push_back(h);
  }
  for (; *p; ++p)
    if (*p != ' ' && *p != '\t' && *p != '\r') return false;
  return true;
}

ExecCrossingsRun run_exec_crossings(const std::string& command, const CasterMesh& mesh, const CasterRays& rays,
                                    const ExecCrossingsOptions& opt) {
  std::vector<CrossingsAnswer> answers(rays.rays.size());
  LineBatchRun r = run_line_batches(
      command, mesh_protocol_head("rayproof-crossings", mesh.vertices, mesh.triangles), {"ray", "rays"}, rays.set,
      rays.names, opt,
      [&](std::size_t i, std::string& msg) {
        const Ray<double>& ray = rays.rays[i];
        msg += exact_point(ray.o) + " " + exact_point(ray.d) + "\n";
      },
      [&](const std::string& line, std::size_t i) { return parse_crossings_answer(line, answers[i].hits); });
  for (std::size_t i = 0; i < answers.size(); ++i)
    if (r.failed[i]) answers[i].hits.clear();
  return with_failures(std::move(answers), std::move(r));
}

}  // namespace rayproof::verify
