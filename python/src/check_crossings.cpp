/// rayproof.check_crossings: a user's all-hits function (a Python function over numpy arrays of
/// rays, answering flat arrays of hits) judged on a mesh against rayproof's exact crossings,
/// through verify::CrossingsJudge (include/rayproof/verify/crossings_check.h): the same ray sets,
/// counts and reproducers as `rayproof check --crossings` and the C++ API.
#include <pybind11/stl.h>

#include <fmt/core.h>

#include <optional>

#include "bindings.h"
#include "judge_py.h"
#include "rayproof/verify/crossings_check.h"

namespace rayproof::python {

namespace {

/// The function's result for n rays: (t, triangle, offsets), or a dict with 't', 'prim' and
/// 'offsets' (Mesh.crossings' own result); offsets has n + 1 entries from 0, never decreasing, up to
/// len(t). Anything else throws (a failed batch).
void read_hits(py::handle obj, std::span<std::vector<verify::CrossingHit>> out) {
  const std::size_t n = out.size();
  py::object t, tri, off;
  if (py::isinstance<py::dict>(obj)) {
    const py::dict d = py::reinterpret_borrow<py::dict>(obj);
    if (!d.contains("t") || !d.contains("prim") || !d.contains("offsets"))
      throw std::runtime_error("the function's dict lacks 't', 'prim' or 'offsets'");
    t = d["t"], tri = d["prim"], off = d["offsets"];
  } else if (py::isinstance<py::tuple>(obj) && py::len(obj) == 3) {
    const py::tuple tu = py::reinterpret_borrow<py::tuple>(obj);
    t = tu[0], tri = tu[1], off = tu[2];
  } else {
    throw std::runtime_error("the function's result is not (t, triangle, offsets) nor a dict with t, prim, offsets");
  }
  const auto offsets = result_column<std::int64_t>(off, n + 1, "offsets", false);
  const std::int64_t* o = offsets.data();
  const auto total = static_cast<std::size_t>(std::max<std::int64_t>(o[n], 0));
  const auto ts = result_column<double>(t, total, "t", false);
  const auto ks = result_column<std::int64_t>(tri, total, "triangle", false);
  if (o[0] != 0) throw std::runtime_error("the function's offsets do not start at 0");
  for (std::size_t i = 0; i < n; ++i)
    if (o[i + 1] < o[i]) throw std::runtime_error(fmt::format("the function's offsets decrease at {}", i));
  for (std::size_t i = 0; i < n; ++i)
    for (std::int64_t k = o[i]; k < o[i + 1]; ++k) out[i].push_back({ts.data()[k], ks.data()[k]});
}

py::dict crossings_dict(const verify::CrossingsTally& tally) {
  py::dict d = counters_dict(tally, verify::kCrossingsCounters, [](const auto&) { return true; });
  d["precision"] = tally.precision == verify::CasterPrecision::float32 ? "float" : "double";
  d["tolerance_ulps"] = tally.tolerance_ulps;
  d["rays_with_findings"] = tally.rays_with_findings;
  py::dict sets;
  for (const auto& s : tally.sets) {
    py::dict e;
    e["rays"] = s.points;
    e["findings"] = s.findings;
    e["cost_ratio"] = ratio(s.judge_seconds, s.contains_seconds);
    sets[py::str(s.set)] = e;
  }
  d["sets"] = sets;
  add_reproducers_and_notes(d, tally);
  d["judge_seconds"] = tally.judge_seconds;
  d["crossings_seconds"] = tally.crossings_seconds;
  d["cost_ratio"] = ratio(tally.judge_seconds, tally.crossings_seconds);
  return d;
}

py::dict check_crossings(py::function fn, py::handle vertices, py::handle triangles, const std::string& precision,
                         std::uint64_t max_ulps, std::size_t random_rays, std::size_t max_rays_per_set,
                         std::uint64_t seed, std::optional<std::vector<std::string>> sets, std::size_t batch,
                         std::size_t reproducers, std::optional<py::tuple> rays, const std::string& mesh_name,
                         int threads) {
  const CheckedMesh arrays = checked_mesh(vertices, triangles);
  verify::CrossingsCheckOptions opt;
  if (precision == "float") opt.precision = verify::CasterPrecision::float32;
  else if (precision != "double") throw py::value_error("precision: '" + precision + "' is neither 'float' nor 'double'");
  if (batch == 0) throw py::value_error("batch: must be at least 1");
  opt.max_ulps = max_ulps;
  opt.random_rays = random_rays;
  opt.max_rays_per_set = max_rays_per_set;
  opt.seed = seed;
  if (sets) opt.sets = *sets;
  opt.batch = batch;
  opt.reproducers = reproducers;
  opt.threads = threads;
  const verify::CasterMesh mesh{arrays.vertices, arrays.triangles, mesh_name};
  UserCalls user;
  const verify::CrossingsFunction crossings = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d,
                                                  std::span<std::vector<verify::CrossingHit>> out) {
    user([&] { read_hits(fn(vec3_array(o), vec3_array(d)), out); });
  };
  verify::CasterRays ray_set;
  if (rays) {
    if (rays->size() != 2) throw py::value_error("rays: expected a pair (origins, directions)");
    const Rows o = rows_of((*rays)[0], "rays[0] (origins)", 3, false), d = rows_of((*rays)[1], "rays[1] (directions)", 3, false);
    const std::size_t n = common_rows({{"rays[0] (origins)", &o}, {"rays[1] (directions)", &d}});
    for (std::size_t i = 0; i < n; ++i) {
      Ray<double> r{{o.row(i)[0], o.row(i)[1], o.row(i)[2]}, {d.row(i)[0], d.row(i)[1], d.row(i)[2]}};
      if (opt.precision == verify::CasterPrecision::float32) r = {r.o.cast<float>().cast<double>(), r.d.cast<float>().cast<double>()};
      ray_set.rays.push_back(r);
    }
    ray_set.set.assign(n, 0);
    ray_set.names = {"user"};
  }
  std::optional<verify::CrossingsJudge> judge;
  prepare_unlocked([&] {
    if (!rays) ray_set = verify::crossings_rays(mesh, opt);
    judge.emplace(mesh);
  });
  std::vector<verify::CrossingsAnswer> answers(ray_set.rays.size());
  std::string error;
  verify::run_crossings(crossings, ray_set.rays, opt.batch, answers, error);
  user.rethrow_interrupt();
  verify::CrossingsTally tally;
  prepare_unlocked([&] { tally = judge->judge(ray_set, answers, opt); });
  if (!error.empty()) tally.notes.push_back("the function raised: " + error);
  return crossings_dict(tally);
}

}  // namespace

void bind_check_crossings(py::module_& m) {
  static const std::string doc = R"(Judge an all-hits function (every crossing of each ray) on a mesh against exact arithmetic.

fn(origins, directions) takes two (n, 3) float64 arrays and returns every hit at t > 0 of each ray,
in increasing t, as flat arrays: a tuple (t, triangle, offsets), ray i's hits being
t[offsets[i]:offsets[i+1]] on triangle[offsets[i]:offsets[i+1]] (offsets: n + 1 integers from 0),
or a dict with keys 't', 'prim', 'offsets' (what Mesh.crossings returns). Each hit is matched
exactly to the contact its triangle meets the ray at: a crossing wants one hit (k sheets through one
point: k), a touch none. The rays: rayproof's sets (leak, graze, face, surface, random, extreme,
invalid; `sets` picks some; precision='float' rounds them to float and counts t in float ulps), or
rays=(origins, directions). An exception fn raises fails that batch's rays and the run goes on.

Returns a dict of counts ()" + count_keys(verify::kCrossingsCounters, std::string_view("Returns a dict of counts (").size()) + R"(),
precision, tolerance_ulps, per-set counts (`sets`), one-line `reproducers`, `notes`, and the cost:
judge_seconds, crossings_seconds (rayproof's own crossings on the same rays) and cost_ratio.
docs/check.md explains each count.)";
  m.def("check_crossings", &check_crossings, py::arg("fn"), py::arg("vertices"), py::arg("triangles"), py::kw_only(),
        py::arg("precision") = "double", py::arg("max_ulps") = 1, py::arg("random_rays") = 2000,
        py::arg("max_rays_per_set") = 5000, py::arg("seed") = 1, py::arg("sets") = py::none(), py::arg("batch") = 4096,
        py::arg("reproducers") = 5, py::arg("rays") = py::none(), py::arg("mesh_name") = "mesh", py::arg("threads") = 0,
        doc.c_str());
}

}  // namespace rayproof::python
