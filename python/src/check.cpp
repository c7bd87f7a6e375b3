/// rayproof.check: a user's Python intersection function against exact, on rayproof's adversarial
/// case families. The function answers coarsely (hit, t), per case or vectorized over numpy arrays;
/// the answers are judged by verify::compare (verify/differential.h), the same judgement as
/// `rayproof verify`.
#include <fmt/core.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

#include "bindings.h"
#include "gen/families.h"
#include "verify/differential.h"

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
  }
  return {};
}

std::string key_of(const io::Case& c) {
  std::string k(1 + sizeof(c.v), '\0');
  k[0] = static_cast<char>(c.kind);
  std::memcpy(k.data() + 1, c.v.data(), sizeof(c.v));
  return k;
}

struct Failure {
  std::string family, case_line, error;
};

/// Thrown (as a C++ exception carrying a Python error) when the user's function breaks the
/// calling contract (not when it raises: that is a failure of the case).
[[noreturn]] void contract_error(const std::string& what) { throw py::type_error(what); }

class Caller {
 public:
  Caller(py::function f, io::Kind kind, bool f32) : f_(std::move(f)), groups_(prim_groups(kind)), f32_(f32) {}

  /// Arguments for cases [b, e): per case (e - b == 1 and !vectorized) 1-D arrays and scalars,
  /// else (n, 3) and (n,) arrays.
  py::tuple arguments(const std::vector<io::Case>& cs, std::size_t b, std::size_t e, bool vectorized) const {
    std::vector<int> widths = {3, 3};
    widths.insert(widths.end(), groups_.begin(), groups_.end());
    py::tuple args(widths.size());
    const auto n = static_cast<py::ssize_t>(e - b);
    std::size_t off = 0;
    for (std::size_t g = 0; g < widths.size(); ++g) {
      const int w = widths[g];
      py::array a;
      if (!vectorized && w == 1) {
        args[g] = py::float_(f32_ ? double(float(cs[b].v[off])) : cs[b].v[off]);
        off += 1;
        continue;
      }
      std::vector<py::ssize_t> shape;
      if (vectorized) shape.push_back(n);
      if (w > 1) shape.push_back(w);
      if (f32_) {
        py::array_t<float> x(shape);
        float* p = x.mutable_data();
        for (std::size_t i = b; i < e; ++i)
          for (int k = 0; k < w; ++k) *p++ = static_cast<float>(cs[i].v[off + std::size_t(k)]);
        a = x;
      } else {
        py::array_t<double> x(shape);
        double* p = x.mutable_data();
        for (std::size_t i = b; i < e; ++i)
          for (int k = 0; k < w; ++k) *p++ = cs[i].v[off + std::size_t(k)];
        a = x;
      }
      args[g] = a;
      off += std::size_t(w);
    }
    return args;
  }

  static io::CaseResult coarse(bool hit, std::optional<double> t) {
    io::CaseResult r;
    r.form = io::AnswerForm::coarse;
    r.contact = hit ? Contact::hit : Contact::miss;
    if (hit && t && !std::isnan(*t)) r.t = *t;
    return r;
  }

  /// One case, per-case calling convention. Returns false (and sets `error`) when f raised.
  bool one(const std::vector<io::Case>& cs, std::size_t i, io::CaseResult& out, std::string& error) const {
    py::object r;
    try {
      r = f_(*arguments(cs, i, i + 1, false));
    } catch (py::error_already_set& e) {
      if (e.matches(PyExc_KeyboardInterrupt) || e.matches(PyExc_SystemExit)) throw;
      error = e.what();
      return false;
    }
    if (py::isinstance<py::bool_>(r) || py::isinstance(r, py::module_::import("numpy").attr("bool_"))) {
      out = coarse(r.cast<bool>(), std::nullopt);
      return true;
    }
    if ((py::isinstance<py::tuple>(r) || py::isinstance<py::list>(r)) && py::len(r) == 2) {
      py::sequence s = r.cast<py::sequence>();
      std::optional<double> t;
      try {
        const bool hit = PyObject_IsTrue(s[0].ptr()) == 1;
        if (!s[1].is_none()) t = s[1].cast<double>();
        out = coarse(hit, t);
        return true;
      } catch (py::cast_error&) {
      }
    }
    contract_error(fmt::format("check: the function returned {} for the case `{}`; expected (hit: bool, t: float or None)",
                               py::repr(r).cast<std::string>(), io::format_case(cs[i])));
  }

  /// Cases [0, n) vectorized. Returns false when f raised (then call one case at a time).
  bool batch(const std::vector<io::Case>& cs, std::vector<io::CaseResult>& out, std::string& error) const {
    const std::size_t n = cs.size();
    py::object r;
    try {
      r = f_(*arguments(cs, 0, n, true));
    } catch (py::error_already_set& e) {
      if (e.matches(PyExc_KeyboardInterrupt) || e.matches(PyExc_SystemExit)) throw;
      error = e.what();
      return false;
    }
    if (!(py::isinstance<py::tuple>(r) || py::isinstance<py::list>(r)) || py::len(r) != 2)
      contract_error(fmt::format("check: the vectorized function returned {}; expected (hit array, t array)",
                                 py::repr(r).attr("__getitem__")(py::slice(0, 200, 1)).cast<std::string>()));
    py::sequence s = r.cast<py::sequence>();
    auto np = py::module_::import("numpy");
    auto hit = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(np.attr("asarray")(s[0], "bool"));
    py::array_t<double, py::array::c_style | py::array::forcecast> t;
    if (!s[1].is_none()) t = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(s[1]);
    if (!hit || hit.ndim() != 1 || static_cast<std::size_t>(hit.shape(0)) != n)
      contract_error(fmt::format("check: the vectorized function's hit array has shape {}; expected ({},)",
                                 py::str(np.attr("shape")(s[0])).cast<std::string>(), n));
    if (!s[1].is_none() && (!t || t.ndim() != 1 || static_cast<std::size_t>(t.shape(0)) != n))
      contract_error(fmt::format("check: the vectorized function's t array has shape {}; expected ({},)",
                                 py::str(np.attr("shape")(s[1])).cast<std::string>(), n));
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      out[i] = coarse(hit.data()[i], t ? std::optional<double>(t.data()[i]) : std::nullopt);
    return true;
  }

 private:
  py::function f_;
  std::vector<int> groups_;
  bool f32_;
};

py::dict stats_dict(const verify::Stats& s, std::optional<std::uint64_t> max_ulps, std::size_t failures) {
  py::dict d;
  d["cases"] = s.cases + failures;
  d["judged"] = s.cases;
  d["false_hits"] = s.false_hit;
  d["false_misses"] = s.false_miss;
  d["failures"] = failures;
  d["t_count"] = s.ulps.size();
  d["t_ulps_median"] = s.ulp_quantile(0.5);
  d["t_ulps_p99"] = s.ulp_quantile(0.99);
  d["t_ulps_max"] = s.ulp_quantile(1.0);
  if (max_ulps) {
    std::size_t over = 0;
    for (auto u : s.ulps) over += u > *max_ulps;
    d["t_over_max_ulps"] = over;
  }
  return d;
}

py::dict check(py::function f, const std::string& kind_name, std::size_t count, std::uint64_t seed,
               const std::string& precision, bool vectorized, std::optional<std::vector<std::string>> family_names,
               std::size_t reproducers, std::optional<std::uint64_t> max_ulps) {
  const io::Kind kind = kind_named(kind_name);
  if (precision != "float" && precision != "double")
    throw py::value_error(fmt::format("precision: expected 'float' or 'double', got '{}'", precision));
  if (count == 0) throw py::value_error("count: must be at least 1");
  if (count > 10'000'000) throw py::value_error(fmt::format("count: {} cases per family is too many (at most 10000000)", count));
  const bool f32 = precision == "float";

  // The families: every one of this kind (and `invalid`, restricted to this kind), or those named.
  std::vector<const gen::Family*> fams;
  if (family_names) {
    for (const auto& n : *family_names) {
      const gen::Family* fam = gen::find_family(n);
      if (!fam) throw py::value_error(fmt::format("families: unknown family '{}' (known: {})", n, gen::family_names()));
      if (!fam->every_kind && fam->kind != kind)
        throw py::value_error(fmt::format("families: '{}' is a {} family, not {}", n, io::to_string(fam->kind), kind_name));
      fams.push_back(fam);
    }
  } else {
    for (const auto& fam : gen::families())
      if (fam.kind == kind || fam.every_kind) fams.push_back(&fam);
  }

  Method meth;
  meth.name = "python";
  meth.summary = "the user's Python function";
  meth.precision = f32 ? Precision::float32 : Precision::float64;
  meth.kinds = {kind};
  std::unordered_map<std::string, io::CaseResult> answers;
  meth.classify = [&answers](const io::Case& c) {
    auto it = answers.find(key_of(c));
    return it == answers.end() ? io::CaseResult{Contact::error} : it->second;
  };
  meth.classify_batch = [&meth](std::span<const io::Case> in, std::span<io::CaseResult> out) {
    for (std::size_t i = 0; i < in.size(); ++i) out[i] = meth.classify(in[i]);
  };

  Caller caller(f, kind, f32);
  py::dict per_family;
  verify::Stats total;
  std::size_t total_failures = 0;
  py::list repro, failures_out;
  std::string table = fmt::format("{:<24} {:>7} {:>10} {:>12} {:>8} {:>10} {:>8} {:>8}\n", "family", "cases",
                                  "false hit", "false miss", "raised", "t med ulp", "p99", "max");
  for (const gen::Family* fam : fams) {
    std::vector<io::Case> cases;
    verify::ExactAnswers exact;
    {
      py::gil_scoped_release unlocked;
      for (auto& c : gen::generate(*fam, count, seed, f32 ? gen::Precision::float32 : gen::Precision::float64))
        if (c.kind == kind) cases.push_back(f32 ? io::round_to_float(c) : c);
    }
    if (cases.empty()) continue;
    // The function's answers; cases it raised on are set aside with the error.
    std::vector<io::CaseResult> got(cases.size());
    std::vector<bool> raised(cases.size(), false);
    std::vector<Failure> fails;
    std::string batch_error;
    const bool batched = vectorized && caller.batch(cases, got, batch_error);  // raised: one case at a time
    if (!batched) {
      for (std::size_t i = 0; i < cases.size(); ++i) {
        std::string err;
        if (vectorized) {
          std::vector<io::Case> one{cases[i]};
          std::vector<io::CaseResult> r;
          if (caller.batch(one, r, err)) {
            got[i] = r[0];
            continue;
          }
        } else if (caller.one(cases, i, got[i], err)) {
          continue;
        }
        raised[i] = true;
        fails.push_back({fam->name, io::format_case(cases[i]), err});
      }
    }
    std::vector<io::Case> judged_cases;
    answers.clear();
    for (std::size_t i = 0; i < cases.size(); ++i)
      if (!raised[i]) {
        judged_cases.push_back(cases[i]);
        answers.emplace(key_of(cases[i]), got[i]);
      }
    verify::Comparison cmp;
    {
      py::gil_scoped_release unlocked;
      exact = verify::exact_answers(judged_cases);
      cmp = verify::compare(judged_cases, exact, {&meth}, reproducers,
                            max_ulps ? *max_ulps : std::numeric_limits<std::uint64_t>::max());
    }
    const verify::Stats s = cmp.total(meth.name);
    total.merge(s);
    total_failures += fails.size();
    per_family[py::str(fam->name)] = stats_dict(s, max_ulps, fails.size());
    table += fmt::format("{:<24} {:>7} {:>10} {:>12} {:>8} {:>10} {:>8} {:>8}\n", fam->name, s.cases + fails.size(),
                         s.false_hit, s.false_miss, fails.size(), s.ulp_quantile(0.5), s.ulp_quantile(0.99),
                         s.ulp_quantile(1.0));
    for (const auto& mm : cmp.mismatches) {
      py::dict r;
      r["family"] = fam->name;
      r["verdict"] = verify::to_string(mm.verdict);
      r["case"] = io::format_case(mm.input);
      r["got"] = io::format_result(mm.got);
      r["want"] = io::format_result(mm.want);
      r["ulps"] = mm.ulps;
      repro.append(r);
    }
    for (const auto& fl : fails) {
      py::dict r;
      r["family"] = fl.family;
      r["case"] = fl.case_line;
      r["error"] = fl.error;
      failures_out.append(r);
    }
  }
  table += fmt::format("{:<24} {:>7} {:>10} {:>12} {:>8} {:>10} {:>8} {:>8}\n", "total", total.cases + total_failures,
                       total.false_hit, total.false_miss, total_failures, total.ulp_quantile(0.5),
                       total.ulp_quantile(0.99), total.ulp_quantile(1.0));
  py::dict out;
  out["kind"] = kind_name;
  out["precision"] = precision;
  out["count"] = count;
  out["seed"] = seed;
  out["families"] = per_family;
  out["total"] = stats_dict(total, max_ulps, total_failures);
  out["reproducers"] = repro;
  out["failures"] = failures_out;
  out["table"] = table;
  return out;
}

}  // namespace

void bind_check(py::module_& m) {
  using namespace pybind11::literals;
  m.def("check", &check, "f"_a, "kind"_a = "triangle", "count"_a = 200, "seed"_a = 1, "precision"_a = "float",
        "vectorized"_a = false, "families"_a = py::none(), "reproducers"_a = 3, "max_ulps"_a = py::none(),
        R"doc(Check a Python intersection function against exact on rayproof's case families.

f answers whether the ray touches the primitive at some t >= 0 and where first:
  per case:    f(o, d, *prim) -> (hit, t)        o, d, points: numpy arrays (3,); radii: float
  vectorized:  f(O, D, *prim) -> (hits, ts)      O, D, points: (n, 3); radii: (n,); results (n,)
  (triangle: f(o, d, p0, p1, p2); sphere: f(o, d, center, radius); plane: point, normal;
  ellipsoid: center, semi_axes; box: lo, hi; disk: center, normal, radius.)
t may be None (or NaN) when the function does not compute it; it is ignored for misses.
precision 'float': cases built in float precision, arrays are float32, t error in float ulps;
'double': float64. Every family of the kind runs (count cases each, from seed; `families` picks
some), and the answers are judged as `rayproof verify` judges them: false hits, false misses
(against the exact class) and t error in ulps of the exact first contact.
A Python exception raised by f is not propagated: the case is listed in 'failures' with the error
and left out of the tallies (KeyboardInterrupt and SystemExit do propagate). A result of the wrong
form raises TypeError.
Returns a dict: 'families' (per family: cases, judged, false_hits, false_misses, failures,
t_count, t_ulps_median, t_ulps_p99, t_ulps_max, and t_over_max_ulps with max_ulps), 'total',
'reproducers' (up to `reproducers` per family: the case line as the function saw it, its answer,
the exact answer, the verdict and the t error; class errors, and t errors above max_ulps when it
is given), 'failures', and 'table' (the tallies as text).)doc");
}

}  // namespace rayproof::python
