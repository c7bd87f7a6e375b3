#pragma once
/// Spawned rays on triangle meshes: primary rays hit a mesh through a
/// MeshCaster (float, robust, certified), the hit point is interpolated from the kernel's
/// barycentrics in the method's precision with pbrt-v4's bound on its error (gamma(7) times
/// sum |b_i v_i| per coordinate, projected on the normal), and three rays leave it by every origin
/// strategy of rayproof/spawn.h: a reflection ray and a shadow ray toward a light on the incoming
/// side, and a shadow ray toward a light behind the surface (through the mesh; thin parts must block
/// it).
///
/// Self-intersection: a crossing at t > 0 of the spawned ray with a triangle it provably cannot
/// meet from the exact hit point: the triangle it leaves, and every neighbour across a shared edge
/// or vertex whose vertices all lie in the closed half-space behind the leaving side of that
/// triangle's plane (a sign decided in double with an error filter; neighbours it cannot decide,
/// and concave neighbours, are not counted). Spawned directions make an angle of at least
/// asin(0.05) with the plane, so the leaving side is never in doubt.
///
/// Visibility of the two shadow rays (segment to the light, t in (0, 1]) is compared with a
/// reference: the certified caster from the certified origin spawned at the certified caster's hit
/// point (barycentrics within 2^-50 of exact, rayproof::certified::intersect). A shadow ray the
/// method finds blocked where the reference is not is a false occlusion; the other way, a leak.
/// Where the reference's first blocker is within 2^-30 of the mesh's size from its origin (a
/// concave crease the hit point sits on, met at t ~ 0) the shadow ray is not compared. A method
/// whose primary ray hits another triangle than the certified caster's (at an edge or vertex)
/// spawns from its own hit and counts self-intersections there; its shadow rays are not compared
/// (the reference leaves another triangle).
/// float and robust cast float-rounded rays: their hit points and spawned origins are floats.
///
/// The mesh's vertices are rounded to float first so that every method sees the same surface.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/spawn.h"

namespace rayproof::light {

struct MeshSpawnCount {
  SpawnStrategy strategy = SpawnStrategy::none;
  std::string method;                 ///< float, robust, certified
  std::uint64_t spawned = 0;          ///< spawned rays (up to 3 per primary hit)
  std::uint64_t primary_misses = 0;   ///< primary rays the method's caster did not see hit
  /// Of those: the certified caster misses the float-rounded primary ray too (float and robust cast
  /// rays rounded to float: a target on a silhouette edge or vertex can lie beside the rounded ray).
  std::uint64_t primary_misses_ray = 0;
  std::uint64_t self_hits = 0;        ///< the method's own caster finds an impossible crossing
  std::uint64_t exact_self_hits = 0;  ///< the certified caster does, on the same spawned ray
  std::uint64_t shadow = 0;           ///< shadow rays compared with the reference visibility
  std::uint64_t false_occlusions = 0; ///< own caster: blocked, reference: visible
  std::uint64_t leaks = 0;            ///< own caster: visible, reference: blocked
  /// Of the false occlusions and leaks: those where the certified caster, cast along the method's
  /// own shadow ray (its origin, its direction), answers as the method did. There the method's hit
  /// point and origin, not its caster, decide; the others are its caster's errors.
  std::uint64_t false_occlusions_ray = 0, leaks_ray = 0;
};

/// A closed test mesh: an octahedron subdivided `subdivisions` times onto the unit sphere and,
/// beside it, a closed slab (a box 2 x 2 x `slab_thickness`), both scaled by `scale` and moved
/// to `offset` (x = y = z).
[[nodiscard]] mesh::Mesh generated_spawn_mesh(int subdivisions, double slab_thickness, double scale, double offset);

/// `trials` primary rays per method (the same rays for every method); rows: method x strategy
/// (float, robust, certified x none, fixed-epsilon, error-bounded, certified). `epsilon` is the
/// fixed-epsilon offset. Throws std::invalid_argument on an empty mesh.
[[nodiscard]] std::vector<MeshSpawnCount> count_mesh_spawn(const mesh::Mesh& m, std::uint64_t trials,
                                                           std::uint64_t seed, double epsilon);

}  // namespace rayproof::light
