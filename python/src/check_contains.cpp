/// rayproof.check_contains and rayproof.check_distance: a user's containment or distance function
/// (a Python function over a numpy array of points) judged on a mesh against rayproof's exact
/// answers, through verify::ContainsJudge and verify::DistanceJudge
/// (include/rayproof/verify/contains_check.h, distance_check.h): the same point sets, counts and
/// reproducers as `rayproof check --contains` / `--distance` and the C++ API.
#include <pybind11/stl.h>

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "bindings.h"
#include "judge_py.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/verify/contains_check.h"
#include "rayproof/verify/distance_check.h"

namespace rayproof::python {

namespace {

/// The function's n answers as int32 sides: integers as they are (garbage beyond 0..2 is the
/// judge's to count), booleans as 0 and 1, floats that are not integers (NaN, 0.5) or beyond int32
/// as ContainsAnswer::kNotAnInteger. A result of the wrong shape or type throws (a failure).
void read_answers(py::handle obj, std::span<std::int32_t> out) {
  const auto d = result_column<double>(obj, out.size(), "result");
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double x = d.data()[i];  // int64 beyond 2^53 rounds, but stays beyond int32: garbage either way
    const bool integer = std::isfinite(x) && x == std::floor(x) && x > std::numeric_limits<std::int32_t>::min() &&
                         x <= std::numeric_limits<std::int32_t>::max();
    out[i] = integer ? static_cast<std::int32_t>(x) : verify::ContainsAnswer::kNotAnInteger;
  }
}

/// The tally as Python's dict: every counter by its key (in kContainsCounters' order), then the
/// rule, per-set counts, reproducers, notes and the judgement's cost.
py::dict result_dict(const verify::ContainsTally& tally) {
  py::dict d = counters_dict(tally, verify::kContainsCounters, [](const auto&) { return true; });
  d["rule"] = std::string(to_string(tally.rule));
  d["sets"] = set_costs_dict(tally.sets);
  add_reproducers_and_notes(d, tally);
  d["judge_seconds"] = tally.judge_seconds;
  d["contains_seconds"] = tally.contains_seconds;
  d["cost_ratio"] = ratio(tally.judge_seconds, tally.contains_seconds);
  return d;
}

/// The user's points as one set named "user".
verify::ContainsPoints user_point_set(py::handle points) {
  verify::ContainsPoints out;
  out.points = user_points(points, "points");
  out.set.assign(out.points.size(), 0);
  out.names = {"user"};
  return out;
}

ContainsRule rule_named(const std::string& name) {
  for (ContainsRule r : {ContainsRule::automatic, ContainsRule::nonzero, ContainsRule::parity, ContainsRule::winding})
    if (name == to_string(r)) return r;
  throw py::value_error(fmt::format("rule: '{}' is not 'automatic', 'nonzero', 'parity' or 'winding'", name));
}

py::dict check_contains(py::function fn, py::handle vertices, py::handle triangles, const std::string& rule,
                        const std::string& precision, std::size_t random_points, std::size_t max_points_per_set, std::uint64_t seed,
                        std::optional<std::vector<std::string>> sets, std::size_t batch, std::size_t reproducers,
                        std::optional<py::handle> points, const std::string& mesh_name, int threads) {
  const CheckedMesh arrays = checked_mesh(vertices, triangles);
  verify::ContainsCheckOptions opt;
  opt.rule = rule_named(rule);
  if (precision == "float") opt.precision = verify::ContainsPrecision::float32;
  else if (precision != "double") throw py::value_error(fmt::format("precision: '{}' is neither 'float' nor 'double'", precision));
  if (batch == 0) throw py::value_error("batch: must be at least 1");
  opt.random_points = random_points;
  opt.max_points_per_set = max_points_per_set;
  opt.seed = seed;
  if (sets) opt.sets = *sets;
  opt.batch = batch;
  opt.reproducers = reproducers;
  opt.threads = threads;
  const verify::ContainsMesh mesh{arrays.vertices, arrays.triangles, mesh_name};

  UserCalls user;
  const verify::ContainsFunction contains = [&](std::span<const Vec3<double>> p, std::span<std::int32_t> side) {
    user([&] { read_answers(fn(vec3_array(p)), side); });
  };
  verify::ContainsPoints point_set;
  std::optional<verify::ContainsJudge> judge;
  if (points && !points->is_none()) point_set = user_point_set(*points);
  prepare_unlocked([&] {
    if (point_set.names.empty()) point_set = verify::contains_points(mesh, opt);
    judge.emplace(mesh, opt.rule);
  });
  std::vector<verify::ContainsAnswer> answers(point_set.points.size());
  std::string error;
  verify::run_contains(contains, point_set.points, opt.batch, answers, error);
  user.rethrow_interrupt();
  verify::ContainsTally tally;
  prepare_unlocked([&] { tally = judge->judge(point_set, answers, opt); });
  if (!error.empty()) tally.notes.push_back("the function raised: " + error);
  return result_dict(tally);
}

/// The function's n closest points: an (n, 3) array of numbers (else throws: a failure).
void read_closest_points(py::handle obj, std::span<verify::DistanceAnswer> out) {
  py::array a;
  try {
    a = py::module_::import("numpy").attr("asarray")(obj);
  } catch (py::error_already_set& e) {
    throw std::runtime_error(fmt::format("the function's points are not an array ({})", e.what()));
  }
  const char k = a.dtype().kind();
  if (!(k == 'f' || k == 'i' || k == 'u') || a.ndim() != 2 || static_cast<std::size_t>(a.shape(0)) != out.size() ||
      a.shape(1) != 3)
    throw std::runtime_error(fmt::format("the function's points have shape {} and dtype {}, expected ({}, 3) numbers",
                                         py::str(a.attr("shape")).cast<std::string>(),
                                         py::str(a.dtype()).cast<std::string>(), out.size()));
  const auto x = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!x) throw std::runtime_error("the function's points cannot be read as numbers");
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double* r = x.data() + 3 * i;
    out[i].point = {r[0], r[1], r[2]};
    out[i].has_point = true;
  }
}

/// The function's answers: n distances, or a tuple (distances, points) or (distances, points,
/// triangles), or a dict with "distance" and optionally "points", "triangles" ("barycentric" and
/// "side" ignored: Mesh.closest_points' dict as it is); a result of the wrong shape or type, or a
/// dict with another key, throws: a failure.
void read_distance_answers(py::handle obj, std::span<verify::DistanceAnswer> out) {
  py::object d = py::reinterpret_borrow<py::object>(obj), points = py::none(), triangles = py::none();
  if (py::isinstance<py::tuple>(obj)) {
    const py::tuple t(py::reinterpret_borrow<py::object>(obj));
    if (t.size() < 2 || t.size() > 3)
      throw std::runtime_error(
          fmt::format("the function returned a tuple of {}, expected (distance, point) or (distance, point, triangle)",
                      t.size()));
    d = t[0], points = t[1];
    if (t.size() == 3) triangles = t[2];
  } else if (py::isinstance<py::dict>(obj)) {
    const py::dict m(py::reinterpret_borrow<py::object>(obj));
    for (const auto& [key, value] : m) {
      const std::string k = py::str(key).cast<std::string>();
      if (k == "distance") d = py::reinterpret_borrow<py::object>(value);
      else if (k == "points") points = py::reinterpret_borrow<py::object>(value);
      else if (k == "triangles") triangles = py::reinterpret_borrow<py::object>(value);
      else if (k != "barycentric" && k != "side")
        throw std::runtime_error("the function's dict has key '" + k + "', not distance, points or triangles");
    }
    if (!m.contains("distance")) throw std::runtime_error("the function's dict has no key 'distance'");
  }
  const auto dv = result_column<double>(d, out.size(), "distance", false);
  for (std::size_t i = 0; i < out.size(); ++i) out[i].distance = dv.data()[i];
  if (!points.is_none()) read_closest_points(points, out);
  if (!triangles.is_none()) {
    const auto tv = result_column<std::int64_t>(triangles, out.size(), "triangle", false);
    for (std::size_t i = 0; i < out.size(); ++i) out[i].triangle = tv.data()[i], out[i].has_triangle = true;
  }
}

py::dict distance_dict(const verify::DistanceTally& tally) {
  py::dict d = counters_dict(tally, verify::kDistanceCounters, [](const auto&) { return true; });
  d["signed"] = tally.signed_distance;
  d["precision"] = tally.precision == verify::ContainsPrecision::float32 ? "float" : "double";
  d["rel_tol"] = tally.rel_tol;
  d["max_rel_error"] = tally.max_rel_error;
  d["sets"] = set_costs_dict(tally.sets);
  add_reproducers_and_notes(d, tally);
  d["judge_seconds"] = tally.judge_seconds;
  d["closest_seconds"] = tally.closest_seconds;
  d["cost_ratio"] = ratio(tally.judge_seconds, tally.closest_seconds);
  return d;
}

py::dict check_distance(py::function fn, py::handle vertices, py::handle triangles, bool signed_distance,
                        const std::string& precision, double rel_tol, std::size_t random_points, std::size_t max_points_per_set, std::uint64_t seed,
                        std::optional<std::vector<std::string>> sets, std::size_t batch, std::size_t reproducers,
                        std::optional<py::handle> points, const std::string& mesh_name, int threads) {
  const CheckedMesh arrays = checked_mesh(vertices, triangles);
  verify::DistanceCheckOptions opt;
  if (!(rel_tol >= 0) || !std::isfinite(rel_tol)) throw py::value_error("rel_tol: must be a finite number >= 0");
  if (batch == 0) throw py::value_error("batch: must be at least 1");
  if (precision == "float") opt.precision = verify::ContainsPrecision::float32;
  else if (precision != "double") throw py::value_error(fmt::format("precision: '{}' is neither 'float' nor 'double'", precision));
  opt.signed_distance = signed_distance;
  opt.rel_tol = rel_tol;
  opt.random_points = random_points;
  opt.max_points_per_set = max_points_per_set;
  opt.seed = seed;
  if (sets) opt.sets = *sets;
  opt.batch = batch;
  opt.reproducers = reproducers;
  opt.threads = threads;
  const bool float32 = opt.precision == verify::ContainsPrecision::float32;
  std::vector<Vec3<double>> rounded;
  if (float32) prepare_unlocked([&] { rounded = verify::float_vertices(arrays.vertices); });
  const verify::ContainsMesh mesh{float32 ? std::span<const Vec3<double>>(rounded) : arrays.vertices, arrays.triangles,
                                  mesh_name};
  UserCalls user;
  const verify::DistanceAnswerFunction distance = [&](std::span<const Vec3<double>> p,
                                                      std::span<verify::DistanceAnswer> out) {
    user([&] { read_distance_answers(fn(vec3_array(p)), out); });
  };
  verify::ContainsPoints point_set;
  std::optional<verify::DistanceJudge> judge;
  if (points && !points->is_none()) {
    point_set = user_point_set(*points);
    if (float32)
      for (Vec3<double>& q : point_set.points) q = {static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z)};
  }
  prepare_unlocked([&] {
    if (point_set.names.empty()) point_set = verify::distance_points(mesh, opt);
    judge.emplace(mesh);
  });
  std::vector<verify::DistanceAnswer> answers(point_set.points.size());
  std::string error;
  verify::run_distance(distance, point_set.points, opt.batch, answers, error);
  user.rethrow_interrupt();
  verify::DistanceTally tally;
  prepare_unlocked([&] { tally = judge->judge(point_set, answers, opt); });
  if (!error.empty()) tally.notes.push_back("the function raised: " + error);
  return distance_dict(tally);
}

}  // namespace

void bind_check_contains(py::module_& m) {
  static const std::string doc = R"(Judge a containment (inside/outside) function on a mesh against exact arithmetic.

fn(points) takes an (n, 3) float64 array and returns n answers: 0 outside, 1 inside, optionally 2
on the surface (ints, bools or integral floats; anything else is garbage). The answers are judged
by `rule` ('automatic', 'nonzero', 'parity', 'winding'; as Mesh.contains). The points: rayproof's
sets (vertex, edge, face, nudged, medial, thin, far, random, invalid; `sets` picks some; precision='float'
rounds them to float and nudges by float ulps, for a float32 function), or points=(n, 3) array. An exception fn raises fails that batch's points (failures, or invalid_failures on points
with a NaN or infinity) and the run goes on.

Returns a dict of counts ()" + count_keys(verify::kContainsCounters, std::string_view("Returns a dict of counts (").size()) + R"(),
the rule that answered, per-set counts (`sets`), one-line `reproducers`, `notes`, and the cost:
judge_seconds, contains_seconds (rayproof's own contains on the same points) and cost_ratio.
docs/check.md explains each count.)";
  m.def("check_contains", &check_contains, py::arg("fn"), py::arg("vertices"), py::arg("triangles"), py::kw_only(),
        py::arg("rule") = "automatic", py::arg("precision") = "double", py::arg("random_points") = 1000, py::arg("max_points_per_set") = 1000,
        py::arg("seed") = 1, py::arg("sets") = py::none(), py::arg("batch") = 4096, py::arg("reproducers") = 5,
        py::arg("points") = py::none(), py::arg("mesh_name") = "mesh", py::arg("threads") = 0, doc.c_str());

  static const std::string distance_doc = R"(Judge a distance (or signed distance) function on a mesh against exact arithmetic.

fn(points) takes an (n, 3) float64 array and returns n distances (signed=True: negative inside, 0
on the surface; nan for a point with a NaN or infinity), or a tuple (distances, closest points
(n, 3)) or (distances, closest points, triangle ids), or a dict with keys 'distance', 'points',
'triangles' (Mesh.closest_points' dict as it is). Each distance is judged against rayproof's exact distance correctly rounded: more than
1 ulp off and more than rel_tol relatively is a finding; closest points off the mesh or not
nearest, and triangles not at the exact distance, are findings too. precision='float' (a float32
function): the mesh and the points rounded to float, errors in float ulps. The points: the sets of
check_contains (`sets` picks some), or points=(n, 3) array. An exception fn raises fails that
batch's points and the run goes on.

Returns a dict of counts ()" + count_keys(verify::kDistanceCounters, std::string_view("Returns a dict of counts (").size()) + R"(),
signed, precision, rel_tol, max_rel_error, per-set counts (`sets`), one-line `reproducers`, `notes`, and the
cost: judge_seconds, closest_seconds (rayproof's own closest points on the same points) and
cost_ratio. docs/check.md explains each count.)";
  m.def("check_distance", &check_distance, py::arg("fn"), py::arg("vertices"), py::arg("triangles"), py::kw_only(),
        py::arg("signed") = false, py::arg("precision") = "double", py::arg("rel_tol") = 0.0, py::arg("random_points") = 1000,
        py::arg("max_points_per_set") = 1000, py::arg("seed") = 1, py::arg("sets") = py::none(),
        py::arg("batch") = 4096, py::arg("reproducers") = 5, py::arg("points") = py::none(),
        py::arg("mesh_name") = "mesh", py::arg("threads") = 0, distance_doc.c_str());
}

}  // namespace rayproof::python
