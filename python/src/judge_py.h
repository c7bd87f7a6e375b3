#pragma once
/// What the Python bindings of the whole-function judges share (check_caster.cpp,
/// check_contains.cpp): items as numpy arrays for the user's function, its
/// results read back as columns, the user's exceptions (an interrupt rethrown, any other one a
/// failed batch), the tally's counters, reproducers and costs as a dict, the docstrings' key lists.
#include <pybind11/stl.h>

#include <fmt/core.h>

#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/verify/judge_counters.h"

namespace rayproof::python {

/// An (n, 3) float64 array of the vectors (rays' origins or directions, points).
inline py::array_t<double> vec3_array(std::span<const Vec3<double>> v) {
  py::array_t<double> a({static_cast<py::ssize_t>(v.size()), py::ssize_t(3)});
  double* p = a.mutable_data();
  for (std::size_t i = 0; i < v.size(); ++i) p[3 * i] = v[i].x, p[3 * i + 1] = v[i].y, p[3 * i + 2] = v[i].z;
  return a;
}

/// A 1-D numeric array of n values from the function's result (`what` names it in the error:
/// "result", "t"); booleans too when `booleans`. Throws std::runtime_error (a failed batch).
template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> result_column(py::handle obj, std::size_t n, const char* what,
                                                                        bool booleans = true) {
  py::array a;
  try {
    a = py::module_::import("numpy").attr("asarray")(obj);
  } catch (py::error_already_set& e) {
    throw std::runtime_error(fmt::format("the function's {} is not an array ({})", what, e.what()));
  }
  const char k = a.dtype().kind();
  if (!(k == 'f' || k == 'i' || k == 'u' || (booleans && k == 'b')))
    throw std::runtime_error(fmt::format("the function's {} has dtype {}, not numbers", what,
                                         py::str(a.dtype()).cast<std::string>()));
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != n)
    throw std::runtime_error(fmt::format("the function's {} has shape {}, expected ({},)", what,
                                         py::str(a.attr("shape")).cast<std::string>(), n));
  auto out = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!out) throw std::runtime_error(fmt::format("the function's {} cannot be read as numbers", what));
  return out;
}

/// Calls the user's function through `call`: a Python exception becomes std::runtime_error (the
/// judge counts the batch failed), except KeyboardInterrupt and SystemExit, kept in `interrupt`
/// to be rethrown once the run stops.
class UserCalls {
 public:
  template <class Call>
  void operator()(Call&& call) {
    try {
      call();
    } catch (py::error_already_set& e) {
      const std::string what = e.what();
      if (is_interrupt(e)) interrupt_.emplace(std::move(e));
      throw std::runtime_error(what);
    }
  }
  /// Rethrows a kept interrupt.
  void rethrow_interrupt() {
    if (interrupt_) throw std::move(*interrupt_);
  }

 private:
  std::optional<py::error_already_set> interrupt_;
};

/// Runs `prepare` with the GIL released, bad mesh arrays and bad options (MeshInputError,
/// std::invalid_argument: MeshNotClosedError, an unknown set) as ValueError.
template <class Prepare>
void prepare_unlocked(Prepare&& prepare) {
  try {
    py::gil_scoped_release unlocked;
    prepare();
  } catch (const MeshInputError& e) {
    throw py::value_error(std::string("vertices/triangles: ") + e.what());
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

/// An (n, 3) array of the user's points, read as Vec3.
inline std::vector<Vec3<double>> user_points(py::handle obj, const char* name) {
  const Rows r = rows_of(obj, name, 3, false);
  std::vector<Vec3<double>> out;
  out.reserve(r.rows);
  for (std::size_t i = 0; i < r.rows; ++i) out.push_back({r.row(i)[0], r.row(i)[1], r.row(i)[2]});
  return out;
}

/// judge / baseline, or None without a baseline time.
inline std::optional<double> ratio(double judge_seconds, double baseline_seconds) {
  if (!(baseline_seconds > 0)) return std::nullopt;
  return judge_seconds / baseline_seconds;
}

/// Every counter by its key (in the table's order, those `shown`): a dict's first keys.
template <class Tally, class Counts, std::size_t N, class Shown>
py::dict counters_dict(const Tally& tally, const verify::JudgeCounter<Counts> (&table)[N], Shown&& shown) {
  py::dict d;
  for (const verify::JudgeCounter<Counts>& counter : table)
    if (shown(counter)) d[py::str(std::string(counter.key))] = verify::count_of(tally, counter);
  return d;
}

/// The reproducers' lines and the notes, added to `d` (after the judge's own keys).
template <class Tally>
void add_reproducers_and_notes(py::dict& d, const Tally& tally) {
  py::list reps;
  for (const auto& r : tally.reproducers) reps.append(r.line);
  d["reproducers"] = reps;
  d["notes"] = tally.notes;
}

/// Per set: points, findings and the cost ratio (sets with judge_seconds and the baseline's
/// contains_seconds).
template <class Sets>
py::dict set_costs_dict(const Sets& sets) {
  py::dict out;
  for (const auto& s : sets) {
    py::dict e;
    e["points"] = s.points;
    e["findings"] = s.findings;
    e["cost_ratio"] = ratio(s.judge_seconds, s.contains_seconds);
    out[py::str(s.set)] = e;
  }
  return out;
}

/// The counters' keys, comma-separated, in lines of at most 100 characters, the first of them
/// after `first_line_used` characters (for the docstrings).
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

}  // namespace rayproof::python
