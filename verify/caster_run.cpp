// Running a caster (rayproof/verify/caster_check.h): its answers gathered batch by batch, with the
// first exception it throws noted, then judged by CasterJudge (caster_check.cpp); and the tally's
// plain-text summary.
#include <fmt/core.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayproof/float_util.h"
#include "rayproof/verify/caster_check.h"
#include "verify/judge_frame.h"

namespace rayproof::verify {

void run_caster(const ClosestCaster& closest, const AnyCaster& any, std::span<const Ray<double>> rays,
                std::size_t batch, std::span<CasterAnswer> out, std::string& error) {
  if (out.size() != rays.size()) throw std::invalid_argument("run_caster: output size differs from ray count");
  std::vector<Vec3<double>> o, d;
  std::vector<double> t;
  std::vector<std::int64_t> tri;
  std::vector<std::uint8_t> occ;
  run_in_batches(
      rays.size(), batch, error,
      [&](std::size_t at, std::size_t n) {
        o.resize(n), d.resize(n), t.assign(n, kNaN<double>), tri.assign(n, -2), occ.assign(n, 2);
        for (std::size_t k = 0; k < n; ++k) o[k] = rays[at + k].o, d[k] = rays[at + k].d;
        closest(o, d, t, tri);
        if (any) any(o, d, occ);  // a failed batch is judged failed: its occlusion answers are not read
      },
      [&](std::size_t at, std::size_t n, bool failed) {
        for (std::size_t k = 0; k < n; ++k) {
          CasterAnswer& a = out[at + k];
          a.t = t[k], a.triangle = tri[k], a.failed = failed;
          a.any = any && !failed ? static_cast<std::int8_t>(occ[k] ? 1 : 0) : std::int8_t(-1);
        }
      });
}

namespace {

/// The caster run on `rays`, then judged; the first exception it threw is noted.
CasterTally run_and_judge(const ClosestCaster& closest, const AnyCaster& any, const CasterMesh& mesh,
                          const CasterRays& rays, const CasterCheckOptions& opt) {
  std::vector<CasterAnswer> answers(rays.rays.size());
  std::string error;
  run_caster(closest, any, rays.rays, opt.batch, answers, error);
  CasterTally tally = CasterJudge(mesh).judge(rays, answers, opt);
  if (!error.empty()) tally.notes.push_back("the caster threw: " + error);
  return tally;
}

}  // namespace

CasterTally check_caster(const ClosestCaster& closest, const CasterMesh& mesh, const CasterCheckOptions& opt,
                         const AnyCaster& any) {
  return run_and_judge(closest, any, mesh, caster_rays(mesh, opt), opt);
}

CasterTally check_caster(const ClosestCaster& closest, const CasterMesh& mesh, std::span<const Ray<double>> user_rays,
                         const CasterCheckOptions& opt, const AnyCaster& any) {
  CasterRays rays;
  rays.rays.assign(user_rays.begin(), user_rays.end());
  rays.set.assign(rays.rays.size(), 0);
  rays.names = {"user"};
  return run_and_judge(closest, any, mesh, rays, opt);
}

std::string summary_text(const CasterTally& tally) {
  std::string text =
      counters_text(kCasterCounters, tally, 18, [&](const CasterCounter& counter) { return shown(tally, counter); });
  for (const auto& set : tally.sets)
    text += fmt::format("set {:<10} rays {:>7}  findings {:>7}  false_miss {}\n", set.set, set.rays, set.findings,
                        set.false_miss);
  return text + notes_text(tally.notes, tally.reproducers);
}

}  // namespace rayproof::verify
