#pragma once
/// The method registry: every way rayproof can answer a case (float, double, exact, robust,
/// certified, alternatives) under one name, so classify, verify, report and fuzz pick them up
/// without knowing them.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/case_file.h"

namespace rayproof {

/// The precision a method is judged in: float methods see float-rounded inputs and their t error
/// is counted in float ulps (docs/cases.md).
enum class Precision { float32, float64 };

/// A user kernel's failure on one case.
struct KernelFailure {
  std::string what;  ///< "crashed (signal 11)", "timed out after 5 s", "exited early (status 3)", "unreadable answer 'x'"
  io::Case input;    ///< the case that caused it, as the kernel saw it
};

/// What a method promises on one kind, checked by verify, report and fuzz against exact.
struct Promise {
  /// No false miss: `all` everywhere; `ahead` wherever the exact first contact is at t > 0 and the
  /// ray does not lie in the primitive's plane (a ray starting on the surface, or a coplanar ray,
  /// may be missed).
  enum class NoFalseMiss : std::uint8_t { none, ahead, all };
  bool exact_class = false;                  ///< the exact contact class on every case
  NoFalseMiss no_false_miss = NoFalseMiss::none;
  std::optional<std::uint64_t> t_ulps{};    ///< class-correct t (and t2) within this many ulps

  [[nodiscard]] bool any() const { return exact_class || no_false_miss != NoFalseMiss::none || t_ulps.has_value(); }
  /// "exact class, t within 1 ulp", "no false miss", "nothing", ...
  [[nodiscard]] std::string describe() const;
};

/// The triangle kernels the scene's BVH compiles into its traversal (no call through the case
/// interface per primitive). robust and certified are compiled for triangles and reach the method's
/// `classify` for other kinds and, for certified, when the filter cannot decide (the exact fallback).
enum class FastKernel : std::uint8_t { none, mt_float, mt_double, cramer_float, cramer_double, watertight_float,
                                       watertight_double, robust, certified };

/// How the scene (src/scene: meshes and BVHs) runs a method: its compiled kernel, and whether the
/// box test must be conservative (Ize 2013) for the method's promise to hold. A method without a
/// compiled kernel runs through `classify` per primitive with conservative boxes.
struct SceneKernel {
  FastKernel kernel = FastKernel::none;
  bool conservative_boxes = true;
};

struct Method {
  std::string name;
  std::string summary;
  Precision precision = Precision::float64;
  /// Kinds the method answers; others are skipped by verify and report (classify says `error`).
  std::vector<io::Kind> kinds;
  /// Answers one case. Must not throw on any input; for float32 methods the caller has already
  /// rounded the inputs (io::round_to_float).
  std::function<io::CaseResult(const io::Case&)> classify;
  /// Optional: how many cases so far needed an exact fallback on the calling thread (certified tier).
  std::function<std::uint64_t()> fallbacks;
  /// Optional: answers many cases at once, out[i] for in[i] (same preconditions as classify).
  /// External kernels stream a batch through their pipe instead of one round trip per case.
  std::function<void(std::span<const io::Case> in, std::span<io::CaseResult> out)> classify_batch{};
  /// Optional: the failures (crash, hang, early exit, unreadable answer) of an external or plugin
  /// kernel since the last call, each with the case that caused it. The failing case's answer is
  /// Contact::error; the kernel is restarted and the run goes on.
  std::function<std::vector<KernelFailure>()> take_failures{};
  /// What the method promises per kind; a kind not listed: nothing.
  std::map<io::Kind, Promise> promises{};
  /// How `rayproof cast --method NAME` and the scene's batch queries run it on a mesh.
  SceneKernel scene{};

  /// The promise on kind k (nothing when none is declared).
  [[nodiscard]] Promise promise(io::Kind k) const;

  [[nodiscard]] bool supports(io::Kind k) const;
  /// Runs the method as a user would: rounds to float first for float32 methods.
  [[nodiscard]] io::CaseResult run(const io::Case& c) const;
  /// Answers out[i] for in[i] as classify does (inputs already rounded for float32 methods),
  /// through classify_batch when the method has one. Unsupported kinds are not filtered here.
  void classify_many(std::span<const io::Case> in, std::span<io::CaseResult> out) const;
};

class MethodRegistry {
 public:
  void add(Method m);
  [[nodiscard]] const Method* find(const std::string& name) const;
  [[nodiscard]] const std::vector<Method>& all() const { return methods_; }
  [[nodiscard]] std::string names() const;  ///< comma-separated, for messages

 private:
  std::vector<Method> methods_;
};

/// Registers the dependency-free methods: float, double and the per-kind alternatives.
void register_fast_methods(MethodRegistry& reg);

/// Registers the robust methods (robust, robust-double) and the triangle alternatives (mt-double,
/// baldwin-weber, plucker): floating point only, no exact arithmetic.
void register_robust_methods(MethodRegistry& reg);

/// Registers the classic triangle/triangle tests on `tritri` cases (moller-float, moller-double,
/// gd-float, gd-double): coarse answers, meets or not (docs/tritri.md).
void register_tritri_methods(MethodRegistry& reg);

/// The promise of an exact method on every kind (tritri included): exact class, no false miss, t
/// within 1 ulp (a pair's answer carries no t).
[[nodiscard]] std::map<io::Kind, Promise> exact_promises();

/// Which classes carry T and T2, per kind (docs/cases.md), to turn a kernel result into a CaseResult.
[[nodiscard]] io::CaseResult make_result(io::Kind kind, Contact c, double t, double t2);

}  // namespace rayproof
