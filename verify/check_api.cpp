/// rayproof/verify/check.h: a user's typed C++ kernel wrapped as a Method and run through verify::check,
/// the engine of `rayproof check` (one judgement for the tool and the library).
#include "rayproof/verify/check.h"

#include <exception>
#include <memory>
#include <type_traits>
#include <utility>
#include <mutex>
#include <stdexcept>

#include "methods/primitive_of.h"
#include "verify/check.h"

namespace rayproof::verify {

bool KernelCheck::promises_kept() const {
  for (const auto& p : promises)
    if (!p.kept) return false;
  return true;
}

std::size_t KernelCheck::cases() const {
  std::size_t n = 0;
  for (const auto& f : families) n += f.cases;
  return n;
}

std::size_t KernelCheck::class_errors() const {
  std::size_t n = 0;
  for (const auto& f : families) n += f.false_hits + f.false_misses + f.wrong_classes;
  return n;
}

namespace {

/// The kernel's failures (exceptions), collected for take_failures.
struct Failures {
  std::mutex mu;
  std::vector<KernelFailure> list;
};

CheckOptions engine_options(io::Kind kind, const KernelCheckOptions& o) {
  if (o.count == 0) throw std::invalid_argument("rayproof::verify::check: count must be at least 1");
  CheckOptions opt;
  opt.count = o.count;
  opt.seed = o.seed;
  opt.ulp_tolerance = o.ulp_tolerance;
  opt.reproducers = o.reproducers;
  opt.promises.watertight = o.watertight;
  opt.promises.exact_class = o.exact_class;
  opt.promises.max_ulps = o.max_ulps;
  for (const auto& name : o.families) {
    const gen::Family* f = gen::find_family(name);
    if (!f) throw std::invalid_argument("rayproof::verify::check: no case family '" + name + "' (rayproof gen --list)");
    if (!f->every_kind && f->kind != kind)
      throw std::invalid_argument("rayproof::verify::check: family '" + name + "' is of kind " +
                                  std::string(io::to_string(f->kind)) + ", the kernel answers " +
                                  std::string(io::to_string(kind)));
    opt.families.push_back(f);
  }
  return opt;
}

KernelCheck summary_of(const CheckResult& r) {
  KernelCheck k;
  for (const auto& f : r.families) {
    FamilyVerdict v;
    v.family = f.family;
    v.cases = f.stats.cases;
    v.false_hits = f.stats.false_hit;
    v.false_misses = f.stats.false_miss;
    v.wrong_classes = f.stats.wrong_hit_class + f.stats.wrong_class;
    v.failures = f.stats.kernel_failures;
    v.over_tolerance = f.over_tolerance;
    v.ulp_median = f.stats.ulp_quantile(0.5);
    v.ulp_p99 = f.stats.ulp_quantile(0.99);
    v.ulp_max = f.stats.ulp_quantile(1.0);
    k.families.push_back(v);
    for (const auto& w : f.worst)
      k.reproducers.push_back({f.family, io::format_case(w.judged.input), io::format_answer(w.judged.got),
                               io::format_result(w.judged.want), to_string(w.judged.verdict), w.judged.ulps});
    for (const auto& fail : f.failures)
      k.reproducers.push_back({f.family, io::format_case(fail.input), "error - -", "", "kernel-failure: " + fail.what, 0});
  }
  for (const auto& p : r.promises) k.promises.push_back({p.promise, p.kept, p.violations});
  return k;
}

/// Wraps the typed kernel as a Method (float kernels see float-rounded cases, as the engine
/// guarantees) and runs the engine.
template <class T, class H, class Prim, class PrimOf>
KernelCheck run(io::Kind kind, const std::function<H(const Ray<T>&, const Prim&)>& kernel, PrimOf prim_of,
                const KernelCheckOptions& o) {
  if (!kernel) throw std::invalid_argument("rayproof::verify::check: the kernel is empty");
  const CheckOptions opt = engine_options(kind, o);
  auto failures = std::make_shared<Failures>();
  Method m;
  m.name = "kernel";
  m.summary = "a C++ callable";
  m.precision = std::is_same_v<T, float> ? Precision::float32 : Precision::float64;
  m.kinds = {kind};
  m.classify = [&kernel, prim_of, kind, failures](const io::Case& c) -> io::CaseResult {
    try {
      const H h = kernel(ray_of<T>(c), prim_of(c));
      return make_result(kind, h.contact, static_cast<double>(h.t), static_cast<double>(h.t2));
    } catch (const std::exception& e) {
      std::lock_guard<std::mutex> lock(failures->mu);
      failures->list.push_back({std::string("threw: ") + e.what(), c});
    } catch (...) {
      std::lock_guard<std::mutex> lock(failures->mu);
      failures->list.push_back({"threw a non-standard exception", c});
    }
    return {Contact::error};
  };
  m.take_failures = [failures] {
    std::lock_guard<std::mutex> lock(failures->mu);
    return std::exchange(failures->list, {});
  };
  return summary_of(check(m, opt));
}

}  // namespace

KernelCheck check(const PlaneKernel<float>& k, const KernelCheckOptions& o) {
  return run<float>(io::Kind::plane, k, [](const io::Case& c) { return plane_of<float>(c); }, o);
}
KernelCheck check(const PlaneKernel<double>& k, const KernelCheckOptions& o) {
  return run<double>(io::Kind::plane, k, [](const io::Case& c) { return plane_of<double>(c); }, o);
}
KernelCheck check(const SphereKernel<float>& k, const KernelCheckOptions& o) {
  return run<float>(io::Kind::sphere, k, [](const io::Case& c) { return sphere_of<float>(c); }, o);
}
KernelCheck check(const SphereKernel<double>& k, const KernelCheckOptions& o) {
  return run<double>(io::Kind::sphere, k, [](const io::Case& c) { return sphere_of<double>(c); }, o);
}
KernelCheck check(const EllipsoidKernel<float>& k, const KernelCheckOptions& o) {
  return run<float>(io::Kind::ellipsoid, k, [](const io::Case& c) { return ellipsoid_of<float>(c); }, o);
}
KernelCheck check(const EllipsoidKernel<double>& k, const KernelCheckOptions& o) {
  return run<double>(io::Kind::ellipsoid, k, [](const io::Case& c) { return ellipsoid_of<double>(c); }, o);
}
KernelCheck check(const BoxKernel<float>& k, const KernelCheckOptions& o) {
  return run<float>(io::Kind::box, k, [](const io::Case& c) { return box_of<float>(c); }, o);
}
KernelCheck check(const BoxKernel<double>& k, const KernelCheckOptions& o) {
  return run<double>(io::Kind::box, k, [](const io::Case& c) { return box_of<double>(c); }, o);
}
KernelCheck check(const DiskKernel<float>& k, const KernelCheckOptions& o) {
  return run<float>(io::Kind::disk, k, [](const io::Case& c) { return disk_of<float>(c); }, o);
}
KernelCheck check(const DiskKernel<double>& k, const KernelCheckOptions& o) {
  return run<double>(io::Kind::disk, k, [](const io::Case& c) { return disk_of<double>(c); }, o);
}
KernelCheck check(const TriangleKernel<float>& k, const KernelCheckOptions& o) {
  return run<float>(io::Kind::triangle, k, [](const io::Case& c) { return triangle_of<float>(c); }, o);
}
KernelCheck check(const TriangleKernel<double>& k, const KernelCheckOptions& o) {
  return run<double>(io::Kind::triangle, k, [](const io::Case& c) { return triangle_of<double>(c); }, o);
}

}  // namespace rayproof::verify
