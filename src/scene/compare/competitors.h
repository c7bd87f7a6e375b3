#pragma once
/// Other ray tracers on the same scene and rays, for `rayproof bench`: Embree 3 (rtcIntersect1,
/// default and RTC_SCENE_FLAG_ROBUST, and its 8- and 16-ray packets, each on a default device and on
/// one capped at max_isa=avx2; when built with Embree) and CGAL's AABB_tree
/// first_intersection (Epick; Epeck, exact constructions, on a subset). Triangles only. CGAL and
/// Embree stay inside this target; callers see only rays in, hit flags out.
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace rayproof::scene::compare {

/// True when `n` is one of the comma-separated `names` (a bench's list of peers to run).
inline bool named_in(const std::string& names, const std::string& n) {
  return ("," + names + ",").find("," + n + ",") != std::string::npos;
}

struct Competitor {
  std::string name;
  double build_s = 0;
  double bytes_per_tri = -1;  ///< -1: not known
  bool threaded = true;       ///< false: runs on one thread whatever is asked (Epeck is not thread-safe)
  std::size_t max_rays = 0;   ///< 0: all; else the caller passes at most this many rays (slow methods)
  /// Closest hit of each ray (t >= 0): out[i] = 1 for a hit.
  std::function<void(std::span<const Ray<double>>, std::span<std::uint8_t>, int threads)> closest;
  /// Any hit (occlusion) of each ray (t >= 0): out[i] = 1 for a hit (Embree: rtcOccluded1; CGAL:
  /// do_intersect).
  std::function<void(std::span<const Ray<double>>, std::span<std::uint8_t>, int threads)> any;
  /// Builds the same structure again on `threads` threads and returns the seconds it took (the
  /// data set-up and the build; Embree's device is created before the clock starts, as a program
  /// creates it once). Empty when not offered.
  std::function<double(int threads)> build_seconds;
  /// Packets of `width` consecutive rays (the caller orders coherent rays, e.g. camera tiles, into
  /// consecutive groups; a last partial packet has its missing lanes switched off): Embree's
  /// rtcIntersect8 / rtcOccluded8 and rtcIntersect16 / rtcOccluded16, each offered when its device
  /// reports that packet width as native.
  struct Packets {
    int width = 8;
    std::function<void(std::span<const Ray<double>>, std::span<std::uint8_t>, int threads)> closest, any;
  };
  std::vector<Packets> packets;
  std::vector<std::string> packet_notes;  ///< a packet width not offered, and why
  /// Embree: the device's max_isa setting ("avx2" for the -avx2 competitors; empty: Embree's default,
  /// the best the CPU and the library allow).
  std::string max_isa;
  /// The instruction set its single-ray kernel runs ("avx512", "avx2", ...; empty: not reported),
  /// the kernel it names, and how that is known. Embree: see embree_selected_kernels.
  std::string isa, kernel, isa_how;
};

/// Every competitor name make_competitors takes, in its order.
[[nodiscard]] const std::vector<std::string>& competitor_names();
/// Throws std::invalid_argument naming the first name of the comma-separated `names` that is not
/// a competitor (empty names and "none" are allowed), and the names it takes.
void check_competitor_names(const std::string& names);

/// Whether CGAL's peers (AABB_tree, Side_of_triangle_mesh) are compiled in: the CMake option
/// RAYPROOF_CGAL_PEERS, off in the README's first command (their one translation unit was the
/// longest job of that build). Without them the cgal-* competitors are absent from `bench`, and
/// `bench contains` / `bench distance` list them with this note.
[[nodiscard]] bool cgal_peers_built();
inline constexpr const char* kCgalPeersNotBuilt = "not built (configure with -DRAYPROOF_CGAL_PEERS=ON)";

[[nodiscard]] bool have_embree();
/// Embree default and robust, the same two on a device with max_isa=avx2, then CGAL Epick and Epeck
/// (each built on construction), those of them named in the comma-separated `names` (checked by
/// check_competitor_names; Embree's are skipped when built without it). Embree builds on
/// `build_threads` threads (0: all).
[[nodiscard]] std::vector<Competitor> make_competitors(const Scene& s,
                                                       const std::string& names = "embree,embree-robust,cgal-epick,cgal-epeck",
                                                       int build_threads = 0);

}  // namespace rayproof::scene::compare
