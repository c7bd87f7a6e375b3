#pragma once
/// The measuring half of `rayproof bench contains`: point sets, timed runs of contains and its
/// competitors (interleaved, one thread), wrong answers against a reference, and the open-mesh runs
/// of the generalized winding number beside a brute force. The tool prints what these return.
#include <array>
#include <cstdint>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/vec3.h"

namespace rayproof::scene::compare {

using PointCodes = std::vector<std::uint8_t>;  ///< side codes: 0 outside, 1 inside, 2 surface (Side's numbers)
using Points = std::vector<Vec3<double>>;
using PointRunner = std::function<void(std::span<const Vec3<double>>, std::span<std::uint8_t>)>;

/// A containment method as the bench times it.
struct TimedMethod {
  std::string name;
  PointRunner run;  ///< empty when the method could not be built here (then `note` says why)
  bool once = false;  ///< timed once (slow: Epeck)
  bool parity = false;  ///< cannot answer `surface`: judged on the points off the surface only
  std::vector<double> rates;  ///< Mpoints/s per run
  std::size_t wrong = 0;
  bool ran = false;
  std::string note;
};

/// A point where the exact method `contains` disagreed with the reference.
struct Disagreement {
  Vec3<double> p;
  std::uint8_t got = 0, want = 0;
};

/// Runs every method `repeat` times, interleaved, on `pts`; counts wrong answers against `truth`
/// (when given). Returns the first three disagreements of the method named `contains`.
std::vector<Disagreement> measure(std::vector<TimedMethod>& ms, const Points& pts, const PointCodes* truth, int repeat);

/// rayproof `contains` on `cm`, the competitors of make_contains_competitors (Epeck only when
/// `epeck`), and rayproof's float and robust casters counting crossings along (1, 1, 1).
[[nodiscard]] std::vector<TimedMethod> contains_methods(const mesh::Mesh& m, const ExactMesh& cm, bool epeck);

/// `n` points uniform in the mesh's bounding box.
[[nodiscard]] Points box_points(const mesh::Mesh& m, std::size_t n, std::mt19937_64& rng);

/// For `nv` sampled vertices: the vertex (on the surface), one ulp off it along each axis, points
/// whose +x and (1, 1, 1) rays pass exactly through it, and a rounded edge midpoint.
[[nodiscard]] Points hard_points(const mesh::Mesh& m, std::size_t nv, double extent, std::mt19937_64& rng);

/// A shape whose inside is known in closed form, evaluated exactly.
struct KnownShape {
  std::string name;
  mesh::Mesh mesh;
  std::function<std::uint8_t(const Vec3<double>&)> truth;
  double lo, hi, step;  ///< the lattice of points tested
};

/// [0, 2]^3, the cube dented to (1, 1, 1) from its top, and |x| + |y| + |z| <= 1.
[[nodiscard]] std::vector<KnownShape> known_shapes();

/// The shape's lattice points and, for those on its surface, the one-ulp neighbours along each axis.
[[nodiscard]] Points lattice_points(const KnownShape& shape);

/// One timed row of the open-mesh run: Mpoints/s over the repeats, and the points whose answer
/// differs from the open mesh's default build (0 for a certified variant; rows on the closed
/// original are not compared).
struct OpenRow {
  std::string name;
  int threads = 1;
  bool closed = false;  ///< measured on the closed original
  double lo = 0, hi = 0;
  double cpu = 0;  ///< one thread: best Mpoints per second of the thread's CPU time (steadier on a loaded machine)
  std::size_t differ = 0;
};

/// contains by the winding rule on an open mesh (a closed one gets 1% of its triangles removed, and
/// is then its own closed original; "generated": the 1.31M-triangle bumpy sphere), beside contains
/// on the closed original (`closed_path`, or the cut mesh's source) on the same points, the open
/// mesh built with each speed-up turned off (WindingTuning: the ablation), both at `threads`
/// threads too when above 1 (and the points at least 2048: below that the batch runs on one
/// thread); every row interleaved over the repeats. And a brute-force double
/// winding number on a prefix of the points sized to take a second or two.
struct OpenRun {
  std::string name, error, closed_name;  ///< closed_name empty: no closed original
  std::string closed_error;              ///< why the closed original was not measured
  std::size_t triangles = 0, closed_triangles = 0, points = 0;
  bool closed = false;
  std::array<std::size_t, 4> sides{};  ///< tally by Side
  std::vector<OpenRow> rows;           ///< rows[0]: the open mesh, default build, one thread
  double first_batch = 0;  ///< seconds of the default build's first batch (which tabulates the caps: CapsField)
  double brute = 0;        ///< brute force, best Mpoints/s
  std::size_t brute_points = 0, compared = 0, wrong = 0, inside = 0;  ///< against the brute force where |w - 1/2| >= 1e-6
};
[[nodiscard]] OpenRun time_open_mesh(const std::string& path, const std::string& closed_path, std::size_t points, int repeat,
                                     int threads, std::mt19937_64& rng);

}  // namespace rayproof::scene::compare
