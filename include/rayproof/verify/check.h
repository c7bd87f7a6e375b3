#pragma once
/// Your own C++ kernel against exact arithmetic: the judgement of `rayproof check`, on a callable
/// of rayproof's public types (component rayproof::verify: CGAL, GMP, MPFR).
///
///   auto mine = [](const Ray<float>& r, const Triangle<float>& t) -> TriangleHit<float> { ... };
///   const verify::KernelCheck k = verify::check(TriangleKernel<float>(mine), {.watertight = true});
///   if (!k.promises_kept()) for (const auto& r : k.reproducers) std::cout << r.case_line << '\n';
///
/// Every built-in case family of the kernel's kind (rayproof gen --list; docs/families.md) runs
/// with a fixed seed and count: half of each family's cases built in float precision, half in
/// double, so the same options give the same cases on every machine. A float kernel gets every
/// input rounded to float and is judged against the exact answer on those rounded inputs, with its
/// t error in float ulps; a double kernel on the inputs as given, in double ulps. The kernel's class
/// is judged as docs/cases.md defines it (false hit, false miss, wrong class); only the fields its class
/// carries are read (t, t2; NaN elsewhere). An exception thrown by the kernel is a kernel failure on
/// that case (reported with the case), not a class error, and the run goes on.
///
/// Thread safety: the kernel is called from the calling thread only; concurrent checks are safe.
/// Bad options (an unknown family, a family of another kind, count 0) throw std::invalid_argument.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "rayproof/box.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/hit.h"
#include "rayproof/plane.h"
#include "rayproof/ray.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle_common.h"

namespace rayproof::verify {

struct KernelCheckOptions {
  std::size_t count = 2000;           ///< cases per family (half float-built, half double-built)
  std::uint64_t seed = 1;
  std::vector<std::string> families;  ///< empty: every built-in family of the kernel's kind
  std::uint64_t ulp_tolerance = 1;    ///< class-correct t errors above this are counted as over tolerance
  std::size_t reproducers = 3;        ///< worst cases kept per family (minimized as `rayproof fuzz` does)
  // The promises you state; each is reported kept or broken.
  bool watertight = false;             ///< no false miss on the exact edge and vertex families
  bool exact_class = false;            ///< no class error anywhere
  std::optional<std::uint64_t> max_ulps;  ///< every class-correct t within this many ulps
};

struct FamilyVerdict {
  std::string family;
  std::size_t cases = 0, false_hits = 0, false_misses = 0, wrong_classes = 0, failures = 0;
  std::size_t over_tolerance = 0;                       ///< class-correct cases with t error > ulp_tolerance
  std::uint64_t ulp_median = 0, ulp_p99 = 0, ulp_max = 0;  ///< t error of class-correct cases (UINT64_MAX: a t missing)
};

struct PromiseVerdict {
  std::string promise;  ///< "watertight", "exact-class", "max-ulps N"
  bool kept = true;
  std::size_t violations = 0;
};

/// One bad case: a docs/cases.md case line (the input as the kernel saw it), the kernel's answer and
/// exact's, as `CLASS T T2` lines.
struct CaseReport {
  std::string family, case_line, kernel_answer, exact_answer;
  std::string verdict;  ///< "false-hit", "false-miss", "wrong-hit-class", "wrong-class", "agree" (t error), "kernel-failure: ..."
  std::uint64_t ulps = 0;
};

struct KernelCheck {
  std::vector<FamilyVerdict> families;
  std::vector<PromiseVerdict> promises;  ///< the ones stated in the options
  std::vector<CaseReport> reproducers;   ///< class errors first, then the largest t errors, per family
  [[nodiscard]] bool promises_kept() const;
  [[nodiscard]] std::size_t cases() const;
  [[nodiscard]] std::size_t class_errors() const;
};

template <class T> using PlaneKernel = std::function<Hit<T>(const Ray<T>&, const Plane<T>&)>;
template <class T> using SphereKernel = std::function<Hit<T>(const Ray<T>&, const Sphere<T>&)>;
template <class T> using EllipsoidKernel = std::function<Hit<T>(const Ray<T>&, const Ellipsoid<T>&)>;
template <class T> using BoxKernel = std::function<Hit<T>(const Ray<T>&, const Box<T>&)>;
template <class T> using DiskKernel = std::function<Hit<T>(const Ray<T>&, const Disk<T>&)>;
template <class T> using TriangleKernel = std::function<TriangleHit<T>(const Ray<T>&, const Triangle<T>&)>;

/// Runs the check; the overload picks the kind and the precision from the kernel's signature.
[[nodiscard]] KernelCheck check(const PlaneKernel<float>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const PlaneKernel<double>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const SphereKernel<float>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const SphereKernel<double>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const EllipsoidKernel<float>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const EllipsoidKernel<double>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const BoxKernel<float>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const BoxKernel<double>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const DiskKernel<float>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const DiskKernel<double>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const TriangleKernel<float>& kernel, const KernelCheckOptions& opt = {});
[[nodiscard]] KernelCheck check(const TriangleKernel<double>& kernel, const KernelCheckOptions& opt = {});

}  // namespace rayproof::verify
