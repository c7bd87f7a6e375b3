// The cost of judging a caster (verify::CasterJudge::judge) beside the certified MeshCaster's own
// time on the same rays, both on one thread (thread-CPU clock), for casters that answer right
// (certified, robust) and one that answers wrong often (float). Prints a table of ratios.
#include <fmt/core.h>

#include <cstdlib>
#include <limits>
#include <random>
#include <string>

#include "bench_common.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/verify/caster_check.h"
#include "scene/scene.h"

namespace {

using namespace rayproof;

template <class Method>
std::vector<verify::CasterAnswer> answers_of(const MeshCaster<Method>& c, const std::vector<Ray<double>>& rays) {
  std::vector<verify::CasterAnswer> out(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const MeshHit h = c.closest(rays[i]);
    out[i].t = h.hit() ? h.t : std::numeric_limits<double>::infinity();
    out[i].triangle = h.hit() ? std::int64_t(h.triangle) : -1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const int subdivisions = argc > 1 ? std::atoi(argv[1]) : 5;
  const int reps = argc > 2 ? std::atoi(argv[2]) : 3;
  mesh::Mesh m = scene::icosphere(subdivisions);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> bump(0.8, 1.2);
  for (auto& v : m.vertices) v = (v * bump(rng)).cast<float>().cast<double>();  // a star (floats: what float casters see)
  const verify::CasterMesh mesh{m.vertices, m.triangles, "star"};
  verify::CasterCheckOptions opt;
  opt.random_rays = 20000;
  opt.threads = 1;
  const verify::CasterRays rays = verify::caster_rays(mesh, opt);
  const VertexArray va(&m.vertices[0].x, m.vertices.size());
  const IndexArray ia{m.triangles[0].data(), m.triangles.size()};
  const MeshCaster<cast::Certified> cert(va, ia);
  const MeshCaster<cast::Robust> robust(va, ia);
  const MeshCaster<cast::Float> flt(va, ia);
  const verify::CasterJudge judge(mesh);

  // The certified caster's own time on the rays (the reference of the ratio).
  double cert_s = 1e300;
  for (int r = 0; r < reps; ++r) {
    const double t0 = bench::thread_seconds();
    const auto a = answers_of(cert, rays.rays);
    cert_s = std::min(cert_s, bench::thread_seconds() - t0);
  }
  fmt::print("mesh: perturbed icosphere, {} triangles; {} rays (every set); one thread, best of {}\n",
             m.triangles.size(), rays.rays.size(), reps);
  fmt::print("certified caster: {:.1f} ns/ray\n\n", 1e9 * cert_s / double(rays.rays.size()));
  fmt::print("{:<10} {:>10} {:>12} {:>10} {:>10}\n", "caster", "findings", "judge ns/ray", "judge/cert", "(target)");
  auto row = [&](const char* name, const std::vector<verify::CasterAnswer>& answers, verify::CasterPrecision p) {
    opt.precision = p;
    double s = 1e300;
    std::size_t findings = 0;
    for (int r = 0; r < reps; ++r) {
      const double t0 = bench::thread_seconds();
      const verify::CasterTally c = judge.judge(rays, answers, opt);
      s = std::min(s, bench::thread_seconds() - t0);
      findings = c.findings();
      if (std::getenv("CASTER_BENCH_SETS") && r == 0) fmt::print("{}", verify::summary_text(c).substr(0, 2000));
    }
    fmt::print("{:<10} {:>10} {:>12.1f} {:>10.2f} {:>10}\n", name, findings, 1e9 * s / double(rays.rays.size()),
               s / cert_s, "<= 2");
  };
  row("certified", answers_of(cert, rays.rays), verify::CasterPrecision::float64);
  row("robust", answers_of(robust, rays.rays), verify::CasterPrecision::float32);
  row("float", answers_of(flt, rays.rays), verify::CasterPrecision::float32);

  // Per ray set: the certified caster's time, and judging the float caster's answers (the one
  // with the most wrong answers), side by side.
  fmt::print("\nper set: judging the certified caster's answers and the float caster's:\n"
             "{:<9} {:>7} {:>12} {:>16} {:>10} {:>10} {:>16} {:>10}\n",
             "set", "rays", "cert ns/ray", "judge cert ns/ray", "ratio", "findings", "judge float ns/ray", "ratio");
  for (std::size_t k = 0; k < rays.names.size(); ++k) {
    verify::CasterRays sub;
    sub.names = rays.names;
    for (std::size_t i = 0; i < rays.rays.size(); ++i)
      if (rays.set[i] == k) sub.rays.push_back(rays.rays[i]), sub.set.push_back(rays.set[i]);
    if (sub.rays.empty()) continue;
    double cs = 1e300, js = 1e300, jc = 1e300;
    std::size_t findings = 0;
    const auto answers = answers_of(flt, sub.rays);
    const auto cert_answers = answers_of(cert, sub.rays);
    for (int r = 0; r < reps; ++r) {
      double t0 = bench::thread_seconds();
      (void)answers_of(cert, sub.rays);
      cs = std::min(cs, bench::thread_seconds() - t0);
      opt.precision = verify::CasterPrecision::float64;
      t0 = bench::thread_seconds();
      (void)judge.judge(sub, cert_answers, opt);
      jc = std::min(jc, bench::thread_seconds() - t0);
      opt.precision = verify::CasterPrecision::float32;
      t0 = bench::thread_seconds();
      findings = judge.judge(sub, answers, opt).findings();
      js = std::min(js, bench::thread_seconds() - t0);
    }
    const double n = double(sub.rays.size());
    fmt::print("{:<9} {:>7} {:>12.1f} {:>16.1f} {:>10.2f} {:>10} {:>16.1f} {:>10.2f}\n", rays.names[k], sub.rays.size(),
               1e9 * cs / n, 1e9 * jc / n, jc / cs, findings, 1e9 * js / n, js / cs);
  }
  return 0;
}
