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
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/verify/contains_check.h"
#include "rayproof/verify/distance_check.h"

namespace rayproof::python {

namespace {

py::array_t<double> points_array(std::span<const Vec3<double>> v) {
  py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t(3)});
  double* p = a.mutable_data();
  for (std::size_t i = 0; i < v.size(); ++i) p[3 * i] = v[i].x, p[3 * i + 1] = v[i].y, p[3 * i + 2] = v[i].z;
  return a;
}

/// The function's n answers as int32 sides: integers as they are (garbage beyond 0..2 is the
/// judge's to count), booleans as 0 and 1, floats that are not integers (NaN, 0.5) or beyond int32
/// as ContainsAnswer::kNotAnInteger. A result of the wrong shape or type throws (a failure).
void read_answers(py::handle obj, std::span<std::int32_t> out) {
  py::array a;
  try {
    a = py::module_::import("numpy").attr("asarray")(obj);
  } catch (py::error_already_set& e) {
    throw std::runtime_error(fmt::format("the function's result is not an array ({})", e.what()));
  }
  const char k = a.dtype().kind();
  if (!(k == 'f' || k == 'i' || k == 'u' || k == 'b'))
    throw std::runtime_error(fmt::format("the function's result has dtype {}, not numbers",
                                         py::str(a.dtype()).cast<std::string>()));
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != out.size())
    throw std::runtime_error(fmt::format("the function's result has shape {}, expected ({},)",
                                         py::str(a.attr("shape")).cast<std::string>(), out.size()));
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!d) throw std::runtime_error("the function's result cannot be read as numbers");
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double x = d.data()[i];  // int64 beyond 2^53 rounds, but stays beyond int32: garbage either way
    const bool integer = std::isfinite(x) && x == std::floor(x) && x > std::numeric_limits<std::int32_t>::min() &&
                         x <= std::numeric_limits<std::int32_t>::max();
    out[i] = integer ? static_cast<std::int32_t>(x) : verify::ContainsAnswer::kNotAnInteger;
  }
}

std::optional<double> ratio(double judge, double contains) {
  if (!(contains > 0)) return std::nullopt;
  return judge / contains;
}

/// The tally as Python's dict: every counter by its key (in kContainsCounters' order), then the
/// rule, per-set counts, reproducers, notes and the judgement's cost.
py::dict result_dict(const verify::ContainsTally& tally) {
  py::dict d;
  for (const verify::ContainsCounter& counter : verify::kContainsCounters)
    d[py::str(std::string(counter.key))] = verify::count_of(tally, counter);
  d["rule"] = std::string(to_string(tally.rule));
  py::dict sets;
  for (const auto& s : tally.sets) {
    py::dict e;
    e["points"] = s.points;
    e["findings"] = s.findings;
    e["cost_ratio"] = ratio(s.judge_seconds, s.contains_seconds);
    sets[py::str(s.set)] = e;
  }
  d["sets"] = sets;
  py::list reps;
  for (const auto& r : tally.reproducers) reps.append(r.line);
  d["reproducers"] = reps;
  d["notes"] = tally.notes;
  d["judge_seconds"] = tally.judge_seconds;
  d["contains_seconds"] = tally.contains_seconds;
  d["cost_ratio"] = ratio(tally.judge_seconds, tally.contains_seconds);
  return d;
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

  std::optional<py::error_already_set> interrupt;
  const verify::ContainsFunction contains = [&](std::span<const Vec3<double>> p, std::span<std::int32_t> side) {
    try {
      read_answers(fn(points_array(p)), side);
    } catch (py::error_already_set& e) {
      const std::string what = e.what();
      if (is_interrupt(e)) interrupt.emplace(std::move(e));
      throw std::runtime_error(what);
    }
  };

  verify::ContainsPoints point_set;
  std::optional<verify::ContainsJudge> judge;
  try {
    if (points && !points->is_none()) {
      const Rows r = rows_of(*points, "points", 3, false);
      for (std::size_t i = 0; i < r.rows; ++i) point_set.points.push_back({r.row(i)[0], r.row(i)[1], r.row(i)[2]});
      point_set.set.assign(point_set.points.size(), 0);
      point_set.names = {"user"};
    } else {
      py::gil_scoped_release unlocked;
      point_set = verify::contains_points(mesh, opt);
    }
    py::gil_scoped_release unlocked;
    judge.emplace(mesh, opt.rule);
  } catch (const MeshInputError& e) {
    throw py::value_error(std::string("vertices/triangles: ") + e.what());
  } catch (const std::invalid_argument& e) {  // MeshNotClosedError, an unknown set
    throw py::value_error(e.what());
  }
  std::vector<verify::ContainsAnswer> answers(point_set.points.size());
  std::string error;
  verify::run_contains(contains, point_set.points, opt.batch, answers, error);
  if (interrupt) throw std::move(*interrupt);
  verify::ContainsTally tally;
  {
    py::gil_scoped_release unlocked;
    tally = judge->judge(point_set, answers, opt);
  }
  if (!error.empty()) tally.notes.push_back("the function raised: " + error);
  return result_dict(tally);
}

/// The counters' keys, comma-separated, in lines of at most 100 characters, the first of them
/// after `first_line_used` characters (for the docstring).
template <class Table>
std::string count_keys(const Table& table, std::size_t first_line_used) {
  std::string text;
  std::size_t line = first_line_used;
  for (const auto& counter : table) {
    const bool last = &counter == &table[std::size(table) - 1];
    const std::string word = std::string(counter.key) + (last ? "" : ",");
    if (!text.empty() && line + 1 + word.size() > 100) text += "\n", line = 0;
    else if (!text.empty()) text += " ", ++line;
    text += word, line += word.size();
  }
  return text;
}

/// The function's n distances (a result of the wrong shape or type throws: a failure).
void read_distances(py::handle obj, std::span<double> out) {
  py::array a;
  try {
    a = py::module_::import("numpy").attr("asarray")(obj);
  } catch (py::error_already_set& e) {
    throw std::runtime_error(fmt::format("the function's result is not an array ({})", e.what()));
  }
  const char k = a.dtype().kind();
  if (!(k == 'f' || k == 'i' || k == 'u'))
    throw std::runtime_error(fmt::format("the function's result has dtype {}, not numbers",
                                         py::str(a.dtype()).cast<std::string>()));
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != out.size())
    throw std::runtime_error(fmt::format("the function's result has shape {}, expected ({},)",
                                         py::str(a.attr("shape")).cast<std::string>(), out.size()));
  const auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!d) throw std::runtime_error("the function's result cannot be read as numbers");
  std::copy(d.data(), d.data() + out.size(), out.begin());
}

py::dict distance_dict(const verify::DistanceTally& tally) {
  py::dict d;
  for (const verify::DistanceCounter& counter : verify::kDistanceCounters)
    d[py::str(std::string(counter.key))] = verify::count_of(tally, counter);
  d["signed"] = tally.signed_distance;
  d["rel_tol"] = tally.rel_tol;
  d["max_rel_error"] = tally.max_rel_error;
  py::dict sets;
  for (const auto& s : tally.sets) {
    py::dict e;
    e["points"] = s.points;
    e["findings"] = s.findings;
    e["cost_ratio"] = ratio(s.judge_seconds, s.contains_seconds);
    sets[py::str(s.set)] = e;
  }
  d["sets"] = sets;
  py::list reps;
  for (const auto& r : tally.reproducers) reps.append(r.line);
  d["reproducers"] = reps;
  d["notes"] = tally.notes;
  d["judge_seconds"] = tally.judge_seconds;
  d["closest_seconds"] = tally.closest_seconds;
  d["cost_ratio"] = ratio(tally.judge_seconds, tally.closest_seconds);
  return d;
}

py::dict check_distance(py::function fn, py::handle vertices, py::handle triangles, bool signed_distance,
                        double rel_tol, std::size_t random_points, std::size_t max_points_per_set, std::uint64_t seed,
                        std::optional<std::vector<std::string>> sets, std::size_t batch, std::size_t reproducers,
                        std::optional<py::handle> points, const std::string& mesh_name, int threads) {
  const CheckedMesh arrays = checked_mesh(vertices, triangles);
  verify::DistanceCheckOptions opt;
  if (!(rel_tol >= 0) || !std::isfinite(rel_tol)) throw py::value_error("rel_tol: must be a finite number >= 0");
  if (batch == 0) throw py::value_error("batch: must be at least 1");
  opt.signed_distance = signed_distance;
  opt.rel_tol = rel_tol;
  opt.random_points = random_points;
  opt.max_points_per_set = max_points_per_set;
  opt.seed = seed;
  if (sets) opt.sets = *sets;
  opt.batch = batch;
  opt.reproducers = reproducers;
  opt.threads = threads;
  const verify::ContainsMesh mesh{arrays.vertices, arrays.triangles, mesh_name};
  std::optional<py::error_already_set> interrupt;
  const verify::DistanceFunction distance = [&](std::span<const Vec3<double>> p, std::span<double> d) {
    try {
      read_distances(fn(points_array(p)), d);
    } catch (py::error_already_set& e) {
      const std::string what = e.what();
      if (is_interrupt(e)) interrupt.emplace(std::move(e));
      throw std::runtime_error(what);
    }
  };
  verify::ContainsPoints point_set;
  std::optional<verify::DistanceJudge> judge;
  try {
    if (points && !points->is_none()) {
      const Rows r = rows_of(*points, "points", 3, false);
      for (std::size_t i = 0; i < r.rows; ++i) point_set.points.push_back({r.row(i)[0], r.row(i)[1], r.row(i)[2]});
      point_set.set.assign(point_set.points.size(), 0);
      point_set.names = {"user"};
    } else {
      py::gil_scoped_release unlocked;
      point_set = verify::distance_points(mesh, opt);
    }
    py::gil_scoped_release unlocked;
    judge.emplace(mesh);
  } catch (const MeshInputError& e) {
    throw py::value_error(std::string("vertices/triangles: ") + e.what());
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
  std::vector<verify::DistanceAnswer> answers(point_set.points.size());
  std::string error;
  verify::run_distance(distance, point_set.points, opt.batch, answers, error);
  if (interrupt) throw std::move(*interrupt);
  verify::DistanceTally tally;
  {
    py::gil_scoped_release unlocked;
    tally = judge->judge(point_set, answers, opt);
  }
  if (!error.empty()) tally.notes.push_back("the function raised: " + error);
  return distance_dict(tally);
}

}  // namespace

void bind_check_contains(py::module_& m) {
  static const std::string doc = R"(Judge a containment (inside/outside) function on a mesh against exact arithmetic.

fn(points) takes an (n, 3) float64 array and returns n answers: 0 outside, 1 inside, optionally 2
on the surface (ints, bools or integral floats; anything else is garbage). The answers are judged
by `rule` ('automatic', 'nonzero', 'parity', 'winding'; as Mesh.contains). The points: rayproof's
sets (vertex, edge, face, nudged, thin, far, random, invalid; `sets` picks some; precision='float'
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
on the surface; nan for a point with a NaN or infinity). Each answer is judged against rayproof's
exact distance correctly rounded: more than 1 ulp off and more than rel_tol relatively is a finding.
The points: the sets of check_contains (`sets` picks some), or points=(n, 3) array. An exception fn
raises fails that batch's points and the run goes on.

Returns a dict of counts ()" + count_keys(verify::kDistanceCounters, std::string_view("Returns a dict of counts (").size()) + R"(),
signed, rel_tol, max_rel_error, per-set counts (`sets`), one-line `reproducers`, `notes`, and the
cost: judge_seconds, closest_seconds (rayproof's own closest points on the same points) and
cost_ratio. docs/check.md explains each count.)";
  m.def("check_distance", &check_distance, py::arg("fn"), py::arg("vertices"), py::arg("triangles"), py::kw_only(),
        py::arg("signed") = false, py::arg("rel_tol") = 0.0, py::arg("random_points") = 1000,
        py::arg("max_points_per_set") = 1000, py::arg("seed") = 1, py::arg("sets") = py::none(),
        py::arg("batch") = 4096, py::arg("reproducers") = 5, py::arg("points") = py::none(),
        py::arg("mesh_name") = "mesh", py::arg("threads") = 0, distance_doc.c_str());
}

}  // namespace rayproof::python
