#pragma once
/// The queries of docs/contains.md: exact point containment ("is p inside?"), segments and a ray's
/// crossings, asked of a rayproof::ExactMesh (rayproof/scene/exact_mesh.h). This header declares
/// their answers (Side, SegmentHit, Crossing, Touch, RayCrossings) and states their contract; the
/// rule and its proof: docs/contains.md.
///
/// Contract:
/// - Input: the arrays of MeshCaster (rayproof/scene/mesh_caster.h, the same checks and MeshInputError).
///   The vertices and indices are copied (packed doubles); the arrays may be freed afterwards.
/// - Closed: vertices with equal coordinates are one vertex; every edge used by an even number of
///   triangles (edges of zero length ignored). A mesh that is not closed (open, holed, cracked, a
///   soup) is answered by ContainsRule::winding, the generalized winding number (winding.h); asking
///   for nonzero or parity on it throws MeshNotClosedError naming the open edges.
/// - Oriented: when moreover every edge is used as often a->b as b->a, the mesh is a closed oriented
///   surface (oriented() is true) and winding() is its exact winding number at p; inside means
///   winding != 0 (the nonzero rule; for a mesh that does not intersect itself the winding number
///   is 0 outside and +1 inside, -1 when the triangles face inwards). A closed mesh whose
///   orientations disagree (oriented() false) is answered by parity: inside means an odd number of
///   crossings. ContainsRule::parity asks for parity on oriented meshes too; on a self-intersecting
///   mesh the two rules differ where the winding number is even and nonzero.
/// - Exact for the double inputs: a point on a triangle (closed: its edges and vertices included)
///   is Side::surface; every other answer is that of the exact winding number (or parity). Ties of
///   the parity ray with edges and vertices are decided by Simulation of Simplicity: no retry, no
///   epsilon. Zero-area triangles are never crossed and are not surface.
/// - A point with a NaN or infinite coordinate is Side::invalid.
/// - ExactMesh::ray_crossings(ray): every crossing of a ray once, with its direction, and the touches apart, exact
///   (any mesh; docs/contains.md, "Crossings").
/// - Threads: queries are const and may run concurrently; the batch calls run on a TBB arena of
///   `threads` threads (0: TBB's default).
/// Link rayproof::scene_certified (its exact fallback for inputs outside the expansions' exponent
/// window uses GMP).
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayproof/float_util.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/scene/winding.h"
#include "rayproof/vec3.h"

namespace rayproof {

/// Where a point is, relative to a closed mesh.
enum class Side : std::uint8_t { outside = 0, inside = 1, surface = 2, invalid = 3 };
[[nodiscard]] const char* to_string(Side s);

/// Inside by the winding number (nonzero; needs an oriented mesh), by crossing parity (needs a
/// closed mesh), or by the generalized winding number w > 1/2 (any mesh; automatic picks it for
/// meshes that are not closed; w = 1/2 exactly is outside; docs/contains.md).
enum class ContainsRule : std::uint8_t { automatic, nonzero, parity, winding };
[[nodiscard]] const char* to_string(ContainsRule r);

/// The mesh is not closed: message says how many edges are open and names one.
class MeshNotClosedError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Where a segment p->q first meets the mesh.
struct SegmentHit {
  Side p_side = Side::invalid, q_side = Side::invalid;  ///< the endpoints' sides (exact)
  bool crosses = false;          ///< the closed segment meets the surface (exact)
  std::uint32_t triangle = MeshHit::kNoTriangle;  ///< the triangle of the first contact
  Contact contact = Contact::miss;  ///< its class: interior, edge, vertex or coplanar (exact)
  /// The first contact's parameter along p + t (q - p), t in [0, 1], within a few ulps (0 when p is
  /// on the surface). Two contacts whose t are that close may be ordered either way.
  double t = kNaN<double>;
};

/// Which way a crossing passes the surface: `in` against the triangle's normal (d . n < 0, into the
/// solid of an outward-facing mesh), `out` along it (d . n > 0).
enum class CrossingDirection : std::uint8_t { in = 0, out = 1 };
[[nodiscard]] const char* to_string(CrossingDirection d);

/// A point where a ray passes from one side of the surface to the other, counted once however
/// many triangles meet there (a shared edge, a vertex's fan).
struct Crossing {
  /// Within one ulp of the exact t of the contact; correctly rounded where contacts lie within a
  /// few ulps of each other, so the listed t never decrease.
  double t = kNaN<double>;
  std::uint32_t triangle = MeshHit::kNoTriangle;  ///< a triangle the perturbed ray crosses there
  CrossingDirection direction = CrossingDirection::in;
};

/// A contact of a ray with the surface that is not a crossing: a point where the surface does not
/// pass from one side to the other (contact edge or vertex: a silhouette; interior: coincident
/// triangles of opposite orientation), or a triangle whose plane holds the ray (contact coplanar:
/// the ray lies along it from t to t2).
struct Touch {
  double t = kNaN<double>, t2 = kNaN<double>;  ///< t2: the end of a coplanar range (else t2 = t)
  std::uint32_t triangle = MeshHit::kNoTriangle;
  Contact contact = Contact::miss;
};

/// Every crossing of one ray in exact t order, and its touches (docs/contains.md, "Crossings").
struct RayCrossings {
  bool valid = false;  ///< false for a ray with a NaN or infinite component or d = 0, or tmin > tmax (or NaN)
  std::vector<Crossing> crossings;
  std::vector<Touch> touches;
  /// (number in) - (number out): on a closed oriented mesh, the winding number at the far end of
  /// the range minus that at its start.
  [[nodiscard]] int net() const {
    int n = 0;
    for (const Crossing& c : crossings) n += c.direction == CrossingDirection::in ? 1 : -1;
    return n;
  }
};
}  // namespace rayproof

// The mesh object these queries are asked of. Programs written to the earlier docs included this
// header for the class, then called ExactMesh (now a deprecated alias in exact_mesh.h).
#include "rayproof/scene/exact_mesh.h"
