/// rayproof.check_caster: a user's whole ray caster (a Python function over numpy arrays of rays)
/// judged on a mesh against exact answers, through verify::check_caster
/// (include/rayproof/verify/caster_check.h): the same ray sets, counts and reproducers as
/// `rayproof check --caster` and the C++ API.
#include <pybind11/stl.h>

#include <fmt/core.h>

#include <cmath>
#include <limits>
#include <optional>

#include "bindings.h"
#include "judge_py.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/verify/caster_check.h"

namespace rayproof::python {

namespace {

/// The tally as Python's dict: every counter by its key (in kCasterCounters' order), then per-set
/// counts, reproducers and notes.
py::dict result_dict(const verify::CasterTally& tally) {
  py::dict d = counters_dict(tally, verify::kCasterCounters, [](const auto&) { return true; });
  py::dict sets;
  for (const auto& s : tally.sets) {
    py::dict e;
    e["rays"] = s.rays;
    e["findings"] = s.findings;
    e["false_miss"] = s.false_miss;
    sets[py::str(s.set)] = e;
  }
  d["sets"] = sets;
  add_reproducers_and_notes(d, tally);
  return d;
}

py::dict check_caster(py::function fn, py::handle vertices, py::handle triangles, std::optional<py::function> any_fn,
                      const std::string& precision, std::size_t random_rays, std::size_t max_rays_per_set,
                      std::uint64_t seed, std::optional<std::vector<std::string>> sets, std::size_t batch,
                      std::size_t reproducers, std::optional<py::tuple> rays, const std::string& mesh_name,
                      int threads) {
  const CheckedMesh arrays = checked_mesh(vertices, triangles);
  const auto& verts = arrays.vertices;
  const auto& tris = arrays.triangles;
  verify::CasterCheckOptions opt;
  if (precision == "float") opt.precision = verify::CasterPrecision::float32;
  else if (precision == "double") opt.precision = verify::CasterPrecision::float64;
  else throw py::value_error(fmt::format("precision: '{}' is neither 'float' nor 'double'", precision));
  if (batch == 0) throw py::value_error("batch: must be at least 1");
  opt.random_rays = random_rays;
  opt.max_rays_per_set = max_rays_per_set;
  opt.seed = seed;
  if (sets) opt.sets = *sets;
  opt.batch = batch;
  opt.reproducers = reproducers;
  opt.threads = threads;
  const verify::CasterMesh mesh{verts, tris, mesh_name};

  UserCalls user;
  verify::ClosestCaster closest = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d,
                                      std::span<double> t, std::span<std::int64_t> tri) {
    user([&] {
      py::object res = fn(vec3_array(o), vec3_array(d));
      if (!py::isinstance<py::tuple>(res) && !py::isinstance<py::list>(res))
        throw std::runtime_error("the function returned " + py::str(res.get_type()).cast<std::string>() +
                                 ", expected a pair (t, triangle)");
      const py::tuple pair(res);
      if (pair.size() != 2)
        throw std::runtime_error(fmt::format("the function returned {} values, expected (t, triangle)", pair.size()));
      const auto tv = result_column<double>(pair[0], o.size(), "t");
      const auto iv = result_column<std::int64_t>(pair[1], o.size(), "triangle");
      for (std::size_t i = 0; i < o.size(); ++i) t[i] = tv.data()[i], tri[i] = iv.data()[i];
    });
  };
  verify::AnyCaster any;
  if (any_fn) {
    any = [&](std::span<const Vec3<double>> o, std::span<const Vec3<double>> d, std::span<std::uint8_t> out) {
      user([&] {
        const auto a = result_column<std::int64_t>((*any_fn)(vec3_array(o), vec3_array(d)), o.size(), "any_fn result");
        for (std::size_t i = 0; i < o.size(); ++i) out[i] = a.data()[i] != 0;
      });
    };
  }

  verify::CasterRays ray_set;
  if (rays) {
    if (rays->size() != 2) throw py::value_error("rays: expected a pair (origins, directions)");
    const Rows o = rows_of((*rays)[0], "rays[0] (origins)", 3, false), d = rows_of((*rays)[1], "rays[1] (directions)", 3, false);
    const std::size_t n = common_rows({{"rays[0] (origins)", &o}, {"rays[1] (directions)", &d}});
    for (std::size_t i = 0; i < n; ++i)
      ray_set.rays.push_back({{o.row(i)[0], o.row(i)[1], o.row(i)[2]}, {d.row(i)[0], d.row(i)[1], d.row(i)[2]}});
    ray_set.set.assign(n, 0);
    ray_set.names = {"user"};
  } else {
    prepare_unlocked([&] { ray_set = verify::caster_rays(mesh, opt); });
  }
  std::vector<verify::CasterAnswer> answers(ray_set.rays.size());
  std::string error;
  verify::run_caster(closest, any, ray_set.rays, opt.batch, answers, error);
  user.rethrow_interrupt();
  verify::CasterTally tally;
  prepare_unlocked([&] { tally = verify::CasterJudge(mesh).judge(ray_set, answers, opt); });
  if (!error.empty()) tally.notes.push_back("the function raised: " + error);
  return result_dict(tally);
}

}  // namespace

bool is_interrupt(const py::error_already_set& e) {
  return e.matches(PyExc_KeyboardInterrupt) || e.matches(PyExc_SystemExit);
}

CheckedMesh checked_mesh(py::handle vertices, py::handle triangles) {
  const py::array v = checked_array(vertices, "vertices", 3, false, DtypeRule::real);
  const py::array ix = checked_array(triangles, "triangles", 3, false, DtypeRule::integer);
  const auto vd = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(v);
  const auto id = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(ix);
  if (!vd || !id) throw py::error_already_set();
  const std::size_t nv = static_cast<std::size_t>(vd.shape(0)), nt = static_cast<std::size_t>(id.shape(0));
  CheckedMesh out;
  out.vertices.resize(nv);
  for (std::size_t i = 0; i < nv; ++i) out.vertices[i] = {vd.data()[3 * i], vd.data()[3 * i + 1], vd.data()[3 * i + 2]};
  out.triangles.resize(nt);
  for (std::size_t i = 0; i < nt; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::int64_t x = id.data()[3 * i + k];
      if (x < 0 || static_cast<std::uint64_t>(x) >= nv)
        throw py::value_error(fmt::format("triangles: row {} has vertex index {} outside [0, {})", i, x, nv));
      out.triangles[i][k] = static_cast<std::uint32_t>(x);
    }
  return out;
}

void bind_check_caster(py::module_& m) {
  static const std::string doc = R"(Judge a whole ray caster on a mesh against exact arithmetic.

fn(origins, directions) takes (n, 3) float64 arrays and returns (t, triangle): the closest crossing
at t > 0 of each ray, t (float) and the triangle's row in `triangles` (int), inf and -1 for a miss.
any_fn(origins, directions), optional, returns n booleans: whether each ray crosses anything.
precision ('double' or 'float') sets the ulps t errors are counted in. The rays: rayproof's sets
(leak, graze, face, surface, random, extreme, invalid; `sets` picks some), or rays=(origins,
directions). An exception fn raises fails that batch's rays (counted in caster_failures, or
invalid_failures on invalid rays), and the run goes on.

Returns a dict of counts ()" + count_keys(verify::kCasterCounters, std::string_view("Returns a dict of counts (").size()) + R"(),
per-set counts (`sets`), one-line `reproducers` and `notes`. docs/check.md explains each count.)";
  m.def("check_caster", &check_caster, py::arg("fn"), py::arg("vertices"), py::arg("triangles"), py::kw_only(),
        py::arg("any_fn") = py::none(), py::arg("precision") = "double", py::arg("random_rays") = 2000,
        py::arg("max_rays_per_set") = 20000, py::arg("seed") = 1, py::arg("sets") = py::none(),
        py::arg("batch") = 4096, py::arg("reproducers") = 5, py::arg("rays") = py::none(),
        py::arg("mesh_name") = "mesh", py::arg("threads") = 0, doc.c_str());
}

}  // namespace rayproof::python
