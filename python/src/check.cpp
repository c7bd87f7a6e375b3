/// rayproof.check: a user's Python intersection function against exact, on rayproof's adversarial
/// case families, through verify::check (verify/check.h), the engine of `rayproof check`: the same
/// cases, the same judgement (verify/differential.h) and the same reproducers.
///
/// The function answers coarsely (hit, t), per case or vectorized over numpy arrays. It becomes a
/// Method whose batches call Python (the GIL is held only while Python runs); an exception it raises
/// makes that case a kernel failure (Contact::error, reported with the case through
/// Method::take_failures), not a crash.
#include <pybind11/stl.h>

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bindings.h"
#include "gen/families.h"
#include "verify/check.h"
#include "verify/check_text.h"
#include "verify/ulp_text.h"

namespace rayproof::python {

namespace {

/// How the primitive's fields after o and d are split into the function's arguments: widths of
/// each group (3 = a point or vector, 1 = a scalar).
std::vector<int> prim_groups(io::Kind k) {
  switch (k) {
    case io::Kind::plane: return {3, 3};         // point, normal
    case io::Kind::sphere: return {3, 1};        // center, radius
    case io::Kind::ellipsoid: return {3, 3};     // center, semi-axes
    case io::Kind::triangle: return {3, 3, 3};   // p0, p1, p2
    case io::Kind::box: return {3, 3};           // lo, hi
    case io::Kind::disk: return {3, 3, 1};       // center, normal, radius
    case io::Kind::tritri: return {3, 3, 3, 3};  // after the first two points: p2, q0, q1, q2
  }
  return {};
}

bool is_interrupt(const py::error_already_set& e) {
  return e.matches(PyExc_KeyboardInterrupt) || e.matches(PyExc_SystemExit);
}

/// The user's function behind the Method interface. Every member is called with the GIL released
/// (from verify::check) and takes it for the Python calls.
class PyKernel {
 public:
  PyKernel(py::function f, io::Kind kind, bool f32, bool vectorized)
      : f_(std::move(f)), groups_(prim_groups(kind)), f32_(f32), vectorized_(vectorized),
        barycentrics_(kind == io::Kind::triangle), pair_(kind == io::Kind::tritri) {}

  void classify_batch(std::span<const io::Case> in, std::span<io::CaseResult> out) {
    py::gil_scoped_acquire locked;
    if (vectorized_) {
      std::string ignored;
      if (batch(in, out, ignored)) return;
      // It raised on the batch: one case at a time finds the cases that raise.
      for (std::size_t i = 0; i < in.size(); ++i) {
        std::string error;
        if (!batch(in.subspan(i, 1), out.subspan(i, 1), error)) fail(in[i], out[i], error);
      }
      return;
    }
    for (std::size_t i = 0; i < in.size(); ++i) {
      std::string error;
      if (!one(in[i], out[i], error)) fail(in[i], out[i], error);
    }
  }

  io::CaseResult classify(const io::Case& c) {
    io::CaseResult r;
    classify_batch({&c, 1}, {&r, 1});
    return r;
  }

  std::vector<KernelFailure> take_failures() { return std::exchange(failures_, {}); }

 private:
  void fail(const io::Case& c, io::CaseResult& out, const std::string& error) {
    out = io::CaseResult{};
    out.form = io::AnswerForm::coarse;  // a coarse Contact::error: a kernel failure (io/case_file.h)
    out.contact = Contact::error;
    failures_.push_back({error, c});
  }

  /// The arguments for cases `cs`: (n, 3) and (n,) arrays when vectorized, else 1-D arrays of 3
  /// and floats for the one case.
  py::tuple arguments(std::span<const io::Case> cs) const {
    std::vector<int> widths = {3, 3};
    widths.insert(widths.end(), groups_.begin(), groups_.end());
    py::tuple args(widths.size());
    std::size_t off = 0;
    for (std::size_t g = 0; g < widths.size(); ++g) {
      const int w = widths[g];
      if (!vectorized_ && w == 1) {
        args[g] = py::float_(cs[0].v[off]);  // float methods' inputs are already rounded: exact
        off += 1;
        continue;
      }
      std::vector<py::ssize_t> shape;
      if (vectorized_) shape.push_back(static_cast<py::ssize_t>(cs.size()));
      if (w > 1) shape.push_back(w);
      if (f32_) args[g] = fill<float>(shape, cs, off, w);
      else args[g] = fill<double>(shape, cs, off, w);
      off += std::size_t(w);
    }
    return args;
  }
  template <class T>
  static py::array_t<T> fill(const std::vector<py::ssize_t>& shape, std::span<const io::Case> cs, std::size_t off, int w) {
    py::array_t<T> x(shape);
    T* p = x.mutable_data();
    for (const auto& c : cs)
      for (int k = 0; k < w; ++k) *p++ = static_cast<T>(c.v[off + std::size_t(k)]);
    return x;
  }

  static io::CaseResult coarse(bool hit, std::optional<double> t, std::optional<double> b1 = std::nullopt,
                               std::optional<double> b2 = std::nullopt) {
    io::CaseResult r;
    r.form = io::AnswerForm::coarse;
    r.contact = hit ? Contact::hit : Contact::miss;
    if (hit && t && !std::isnan(*t)) r.t = *t;
    if (hit && b1 && b2) r.b1 = *b1, r.b2 = *b2;  // judged against the exact barycentrics (NaN: the worst)
    return r;
  }

  /// One case, per-case convention. False (with the message) when the function raised.
  bool one(const io::Case& c, io::CaseResult& out, std::string& error) const {
    py::object r;
    try {
      r = f_(*arguments({&c, 1}));
    } catch (py::error_already_set& e) {
      if (is_interrupt(e)) throw;
      error = e.what();
      return false;
    }
    if (py::isinstance<py::bool_>(r) || py::isinstance(r, py::module_::import("numpy").attr("bool_"))) {
      out = pair_ ? io::pair_coarse(r.cast<bool>()) : coarse(r.cast<bool>(), std::nullopt);
      return true;
    }
    if (pair_)  // two triangles: whether they meet, nothing else
      throw py::type_error(fmt::format("check: the function returned {} for the pair `{}`; expected a bool (they meet)",
                                       py::repr(r).cast<std::string>(), io::format_case(c)));
    const std::size_t len = (py::isinstance<py::tuple>(r) || py::isinstance<py::list>(r)) ? py::len(r) : 0;
    if (len == 2 || (len == 4 && barycentrics_)) {
      py::sequence s = r.cast<py::sequence>();
      try {
        std::optional<double> t, b1, b2;
        if (!s[1].is_none()) t = s[1].cast<double>();
        if (len == 4 && !s[2].is_none() && !s[3].is_none()) b1 = s[2].cast<double>(), b2 = s[3].cast<double>();
        const int hit = PyObject_IsTrue(s[0].ptr());
        if (hit < 0) throw py::error_already_set();
        out = coarse(hit == 1, t, b1, b2);
        return true;
      } catch (py::cast_error&) {
      } catch (py::error_already_set& e) {
        if (is_interrupt(e)) throw;
      }
    }
    throw py::type_error(fmt::format("check: the function returned {} for the case `{}`; expected (hit: bool, t: float or None){}",
                                     py::repr(r).cast<std::string>(), io::format_case(c),
                                     barycentrics_ ? " or (hit, t, b1, b2)" : ""));
  }

  /// Cases `cs` in one vectorized call. False (with the message) when the function raised.
  bool batch(std::span<const io::Case> cs, std::span<io::CaseResult> out, std::string& error) const {
    const std::size_t n = cs.size();
    py::object r;
    try {
      r = f_(*arguments(cs));
    } catch (py::error_already_set& e) {
      if (is_interrupt(e)) throw;
      error = e.what();
      return false;
    }
    auto np = py::module_::import("numpy");
    if (pair_) return pair_batch(np, r, out);
    const std::size_t len = (py::isinstance<py::tuple>(r) || py::isinstance<py::list>(r)) ? py::len(r) : 0;
    if (len != 2 && !(len == 4 && barycentrics_))
      throw py::type_error(fmt::format("check: the vectorized function returned {}; expected (hit array, t array){}",
                                       py::repr(r).attr("__getitem__")(py::slice(0, 200, 1)).cast<std::string>(),
                                       barycentrics_ ? " or (hit, t, b1, b2 arrays)" : ""));
    py::sequence s = r.cast<py::sequence>();
    const auto shape_of = [&](py::handle x) { return py::str(np.attr("shape")(x)).cast<std::string>(); };
    py::array_t<bool, py::array::c_style | py::array::forcecast> hit;
    py::array_t<double, py::array::c_style | py::array::forcecast> t, b1, b2;
    const bool with_b = len == 4 && !s[2].is_none() && !s[3].is_none();
    try {
      hit = np.attr("asarray")(s[0], "bool");
      if (!s[1].is_none()) t = np.attr("asarray")(s[1], "float64");
      if (with_b) b1 = np.attr("asarray")(s[2], "float64"), b2 = np.attr("asarray")(s[3], "float64");
    } catch (py::error_already_set& e) {
      if (is_interrupt(e)) throw;
      throw py::type_error(fmt::format("check: the vectorized function's answer is not (bool array, float array): {}", e.what()));
    }
    if (hit.ndim() != 1 || static_cast<std::size_t>(hit.shape(0)) != n)
      throw py::type_error(fmt::format("check: the vectorized function's hit array has shape {}; expected ({},)",
                                       shape_of(s[0]), n));
    if (!s[1].is_none() && (t.ndim() != 1 || static_cast<std::size_t>(t.shape(0)) != n))
      throw py::type_error(fmt::format("check: the vectorized function's t array has shape {}; expected ({},)",
                                       shape_of(s[1]), n));
    if (with_b && (b1.ndim() != 1 || b2.ndim() != 1 || static_cast<std::size_t>(b1.shape(0)) != n ||
                   static_cast<std::size_t>(b2.shape(0)) != n))
      throw py::type_error(fmt::format("check: the vectorized function's b1, b2 arrays have shapes {}, {}; expected ({},)",
                                       shape_of(s[2]), shape_of(s[3]), n));
    for (std::size_t i = 0; i < n; ++i)
      out[i] = coarse(hit.data()[i], s[1].is_none() ? std::nullopt : std::optional<double>(t.data()[i]),
                      with_b ? std::optional<double>(b1.data()[i]) : std::nullopt,
                      with_b ? std::optional<double>(b2.data()[i]) : std::nullopt);
    return true;
  }

  /// A vectorized pair function's answer: one bool array of n (they meet).
  bool pair_batch(py::module_& np, const py::object& r, std::span<io::CaseResult> out) const {
    const std::size_t n = out.size();
    py::array_t<bool, py::array::c_style | py::array::forcecast> hit;
    try {
      hit = np.attr("asarray")(r, "bool");
    } catch (py::error_already_set& e) {
      if (is_interrupt(e)) throw;
      throw py::type_error(fmt::format("check: the vectorized pair function's answer is not a bool array: {}", e.what()));
    }
    if (hit.ndim() != 1 || static_cast<std::size_t>(hit.shape(0)) != n)
      throw py::type_error(fmt::format("check: the vectorized pair function returned shape {}; expected ({},) bools",
                                       py::str(np.attr("shape")(r)).cast<std::string>(), n));
    for (std::size_t i = 0; i < n; ++i) out[i] = io::pair_coarse(hit.data()[i]);
    return true;
  }

  py::function f_;
  std::vector<int> groups_;
  bool f32_, vectorized_, barycentrics_, pair_;
  std::vector<KernelFailure> failures_;
};

py::dict stats_dict(const verify::Stats& s, std::size_t over, std::size_t failures) {
  py::dict d;
  d["cases"] = s.cases;
  d["judged"] = s.cases - failures;
  d["false_hits"] = s.false_hit;
  d["false_misses"] = s.false_miss;
  d["failures"] = failures;
  d["t_count"] = s.ulps.size();
  d["t_ulps_median"] = s.ulp_quantile(0.5);
  d["t_ulps_p99"] = s.ulp_quantile(0.99);
  d["t_ulps_max"] = s.ulp_quantile(1.0);
  d["t_over_tolerance"] = over;
  d["bary_count"] = s.bary_errors.size();
  d["bary_error_max"] = s.bary_errors.empty() ? 0.0 : *std::max_element(s.bary_errors.begin(), s.bary_errors.end());
  return d;
}

py::dict check(py::object f_obj, const std::string& kind_name, std::size_t count, std::uint64_t seed,
               const std::string& precision, bool vectorized, std::optional<std::vector<std::string>> family_names,
               std::size_t reproducers, std::uint64_t ulp_tolerance, bool watertight, bool exact_class,
               std::optional<std::uint64_t> max_ulps, bool minimize, py::object progress) {
  if (!PyCallable_Check(f_obj.ptr()))
    throw py::type_error(fmt::format("f: expected a callable, got {}", py::repr(f_obj).cast<std::string>()));
  if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
    throw py::type_error(fmt::format("progress: expected a callable or None, got {}", py::repr(progress).cast<std::string>()));
  const io::Kind kind = kind_named(kind_name);
  if (precision != "float" && precision != "double")
    throw py::value_error(fmt::format("precision: expected 'float' or 'double', got '{}'", precision));
  if (count == 0) throw py::value_error("count: must be at least 1");
  if (count > 10'000'000) throw py::value_error(fmt::format("count: {} cases per family is too many (at most 10000000)", count));
  const bool f32 = precision == "float";

  verify::CheckOptions opt;
  if (family_names) {
    for (const auto& n : *family_names) {
      const gen::Family* fam = gen::find_family(n);
      if (!fam) throw py::value_error(fmt::format("families: unknown family '{}' (known: {})", n, gen::family_names()));
      if (!fam->every_kind && fam->kind != kind)
        throw py::value_error(fmt::format("families: '{}' is a {} family, not {}", n, io::to_string(fam->kind), kind_name));
      opt.families.push_back(fam);
    }
    if (opt.families.empty()) throw py::value_error("families: empty list (None runs every family of the kind)");
  }
  opt.count = count;
  opt.seed = seed;
  opt.ulp_tolerance = ulp_tolerance;
  opt.reproducers = reproducers;
  opt.minimize = minimize;
  opt.promises.watertight = watertight;
  opt.promises.exact_class = exact_class;
  opt.promises.max_ulps = max_ulps;
  if (!progress.is_none())
    opt.progress = [progress](const verify::CheckProgress& p) {
      py::gil_scoped_acquire locked;
      progress(p.family, p.families_done, p.families_total);
    };

  PyKernel kernel(py::reinterpret_borrow<py::function>(f_obj), kind, f32, vectorized);
  Method meth;
  meth.name = "python";
  meth.summary = "the user's Python function";
  meth.precision = f32 ? Precision::float32 : Precision::float64;
  meth.kinds = {kind};
  meth.classify = [&kernel](const io::Case& c) { return kernel.classify(c); };
  meth.classify_batch = [&kernel](std::span<const io::Case> in, std::span<io::CaseResult> out) {
    kernel.classify_batch(in, out);
  };
  meth.take_failures = [&kernel] { return kernel.take_failures(); };

  verify::CheckResult res;
  {
    py::gil_scoped_release unlocked;
    res = verify::check(meth, opt);
  }

  py::dict per_family;
  py::list repro, failures_out;
  for (const auto& fc : res.families) {
    per_family[py::str(fc.family)] = stats_dict(fc.stats, fc.over_tolerance, fc.failures.size());
    for (const auto& w : fc.worst) {
      py::dict r;
      r["family"] = w.family;
      r["verdict"] = verify::to_string(w.judged.verdict);
      r["case"] = io::format_case(w.judged.input);
      r["got"] = w.judged.input.kind == io::Kind::tritri ? io::format_answer(w.judged.got) : io::format_result(w.judged.got);
      r["want"] = io::format_result(w.judged.want);
      r["ulps"] = w.judged.ulps;
      // The t error in report's words; none for a class error, whose t is not compared.
      r["t_error"] = w.judged.verdict == verify::Verdict::agree ? py::object(py::str(verify::ulp_text(w.judged.ulps, res.precision)))
                                                                : py::object(py::none());
      r["minimized"] = w.minimized;
      repro.append(r);
    }
    for (const auto& kf : fc.failures) {
      py::dict r;
      r["family"] = fc.family;
      r["case"] = io::format_case(kf.input);
      r["error"] = kf.what;
      failures_out.append(r);
    }
  }
  const verify::Stats total = res.total();
  py::list promises;
  for (const auto& p : res.promises) {
    py::dict d;
    d["promise"] = p.promise;
    d["kept"] = p.kept;
    d["violations"] = p.violations;
    promises.append(d);
  }
  py::dict out;
  out["kind"] = kind_name;
  out["precision"] = precision;
  out["count"] = count;
  out["seed"] = seed;
  out["families"] = per_family;
  out["total"] = stats_dict(total, res.over_tolerance(), res.failures());
  out["reproducers"] = repro;
  out["failures"] = failures_out;
  out["promises"] = promises;
  out["promises_kept"] = res.promises_kept();
  out["table"] = verify::check_table(res);  // the table `rayproof check` prints
  return out;
}

}  // namespace

void bind_check(py::module_& m) {
  using namespace pybind11::literals;
  m.def("check", &check, "f"_a, "kind"_a = "triangle", "count"_a = 200, "seed"_a = 1, "precision"_a = "float",
        "vectorized"_a = false, "families"_a = py::none(), "reproducers"_a = 3, "ulp_tolerance"_a = 1,
        "watertight"_a = false, "exact_class"_a = false, "max_ulps"_a = py::none(), "minimize"_a = true,
        "progress"_a = py::none(),
        R"doc(Check a Python intersection function against exact on rayproof's case families.

f answers whether the ray touches the primitive at some t >= 0, and where first:
  per case:    f(o, d, *prim) -> (hit, t)        o, d, points: numpy arrays (3,); radii: float
  vectorized:  f(O, D, *prim) -> (hits, ts)      O, D, points: (n, 3); radii: (n,); results (n,)
  (triangle: f(o, d, p0, p1, p2); sphere: center, radius; plane: point, normal; ellipsoid:
  center, semi_axes; box: lo, hi; disk: center, normal, radius.)
kind 'tritri' (two triangles, no ray): f(p0, p1, p2, q0, q1, q2) -> bool, whether the closed
  triangles meet; vectorized, six (n, 3) arrays -> a bool array (n,). 'false_hits' are then pairs
  called meeting that are disjoint, 'false_misses' meeting pairs called disjoint (docs/tritri.md).
t may be None (or NaN) when f does not compute it; it is ignored for misses. A triangle function
may return (hit, t, b1, b2) with the barycentrics of p1 and p2: they are judged against the exact
ones (absolute error; 'bary_count', 'bary_error_max').
precision 'float': f is a float kernel: it gets float32 arrays of the float-rounded inputs and its
t error is counted in float ulps; 'double': float64.
This is `rayproof check` (verify::check): every family of the kind (or `families`), count cases
each (half built in float precision, half in double) from seed, judged as `rayproof verify` judges:
false hits and false misses against the exact class, t error in ulps of the exact first contact.
A Python exception raised by f does not propagate: the case is listed in 'failures' with the
error (KeyboardInterrupt and SystemExit do propagate). An answer of the wrong form raises TypeError.
Promises (watertight: no false miss on tri_edge/tri_vertex; exact_class: no class error; max_ulps)
are reported kept or broken in 'promises'.
progress: called as progress(family, families_done, families_total) after each family.
Returns a dict: 'families' (per family: cases, judged, false_hits, false_misses, failures, t_count,
t_ulps_median, t_ulps_p99, t_ulps_max, t_over_tolerance, bary_count, bary_error_max), 'total', 'reproducers' (the worst
`reproducers` cases per family as case lines, as f saw them, minimized when `minimize`: f's
answer, the exact one, the verdict, the t error in ulps), 'failures', 'promises',
'promises_kept' and 'table' (the tallies as text).)doc");
}

}  // namespace rayproof::python
