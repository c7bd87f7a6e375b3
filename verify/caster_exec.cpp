// The --caster line protocol: a caster program fed the mesh once and batches of rays
// (verify/caster_exec.h; docs/check.md, "Whole casters"), run by run_line_batches (judge_frame.h).
#include "verify/caster_exec.h"

#include "verify/judge_frame.h"

namespace rayproof::verify {

bool parse_caster_answer(const std::string& line, double& t, long long& triangle) {
  return parse_fields(line, "di", &t, &triangle);
}

ExecCasterRun run_exec_caster(const std::string& command, const CasterMesh& mesh, const CasterRays& rays,
                              const ExecCasterOptions& opt) {
  std::vector<CasterAnswer> answers(rays.rays.size());
  LineBatchRun r = run_line_batches(
      command, mesh_protocol_head("rayproof-caster", mesh.vertices, mesh.triangles), {"ray", "rays"}, rays.set,
      rays.names, opt,
      [&](std::size_t i, std::string& msg) {
        const Ray<double>& ray = rays.rays[i];
        msg += exact_point(ray.o) + " " + exact_point(ray.d) + "\n";
      },
      [&](const std::string& line, std::size_t i) {
        double t;
        long long tri;
        if (!parse_caster_answer(line, t, tri)) return false;
        answers[i].t = t, answers[i].triangle = tri;
        return true;
      });
  return with_failures(std::move(answers), std::move(r));
}

}  // namespace rayproof::verify
