#pragma once
/// Which instruction sets the sides of `rayproof bench` run. Ours: the node path of a built
/// scene::Accel, the leaf path (detail::leaf_simd) and the CPU features they are chosen from.
/// Embree's: the kernels its device selects, as Embree itself reports them. Embree 3 has no device
/// property for its ISA; a device created with verbose=3 prints, when a scene is committed, the
/// intersectors it selected, each in its ISA's namespace
/// ("  intersector1  = avx512::BVH8Triangle4Intersector1Moeller").
#include <string>
#include <utility>
#include <vector>

namespace rayproof::scene {
class Accel;
}

namespace rayproof::scene::compare {

struct OurIsa {
  std::string nodes;   ///< to_string(Accel::simd()): "avx2-8wide" or "sse-4wide"
  std::string leaves;  ///< to_string(detail::leaf_simd()): "avx2", "sse", "scalar" or "off"
  /// avx2, fma, avx512f, and whether the CPU has each (__builtin_cpu_supports).
  std::vector<std::pair<std::string, bool>> cpu;
};

/// The paths `a`'s queries take on this machine (the SIMD leaves as set now: RAYPROOF_SIMD, or a
/// test's force_leaf_simd).
[[nodiscard]] OurIsa our_isa(const Accel& a);

/// One intersector Embree reports as selected.
struct EmbreeKernel {
  std::string width;  ///< "1", "4", "8", "16" or "N" (streams), from "intersector1" etc.
  std::string isa;    ///< its namespace: "sse2", "sse42", "avx", "avx2", "avx512"
  std::string name;   ///< the whole name, "avx512::BVH8Triangle4Intersector1Moeller"
};

struct EmbreeKernels {
  std::vector<EmbreeKernel> kernels;  ///< empty: no report found
  [[nodiscard]] const EmbreeKernel* find(const std::string& width) const {
    for (const auto& k : kernels)
      if (k.width == width) return &k;
    return nullptr;
  }
};

/// The intersectors of the last "selected scene intersector" block of an Embree 3 verbose report
/// (empty when there is none).
[[nodiscard]] EmbreeKernels parse_selected_kernels(const std::string& report);

/// The intersectors Embree selects for a triangle scene (RTC_SCENE_FLAG_ROBUST when `robust`) on a
/// device of configuration `config` ("threads=1,max_isa=avx2"; empty: the defaults): a device of
/// that configuration plus verbose=3 commits a one-triangle scene, its report captured from
/// std::cout. Empty without Embree or when the report has no such block.
[[nodiscard]] EmbreeKernels embree_selected_kernels(const std::string& config, bool robust);

}  // namespace rayproof::scene::compare
