/// rayproof distance MESH POINTS [--signed] [--json]: the distance from each point to the mesh,
/// its side and a nearest triangle (rayproof/scene/distance.h, docs/distance.md). One line per
/// point: `DIST SIDE TRI`; --signed puts the signed distance first (`SIGNED DIST SIDE TRI`,
/// negative inside); --json prints one object with the closest points and barycentrics too.
/// The point file is read as `rayproof contains` reads it (x y z per line); errors (exit 2, one
/// message): a missing or unreadable file, a mesh without triangles, a malformed line, a NaN or
/// infinite coordinate.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/mesh_input.h"
#include "cli/commands.h"
#include "cli/input.h"
#include "cli/point_lines.h"
#include "io/case_file.h"
#include "mesh/mesh.h"
#include "rayproof/scene/distance.h"

namespace rayproof::cli {

namespace {

struct DistanceOptions {
  std::string mesh, points;
  bool json = false, signed_first = false;
  int threads = 0;
};

int run_distance(const DistanceOptions& opt) {
  const char* me = "rayproof distance";
  auto loaded = read_closed_mesh(me, opt.mesh);
  if (!loaded) return 2;
  const std::unique_ptr<ExactMesh>& cm = loaded->closed;
  Input in = open_input(opt.points);
  if (!in.stream) {
    fmt::print(stderr, "{}: {}\n", me, in.error);
    return 2;
  }
  std::vector<double> xs;
  std::string error;
  if (!read_numbers(*in.stream, opt.points, 3, xs, error)) {
    fmt::print(stderr, "{}: {}\n", me, error);
    return 2;
  }
  const std::size_t n = xs.size() / 3;
  std::vector<ClosestPoint> res(n);
  cm->closest_points(std::span<const Vec3<double>>(reinterpret_cast<const Vec3<double>*>(xs.data()), n), res, true,
                     opt.threads);
  std::size_t sides[4] = {0, 0, 0, 0}, stages[5] = {0, 0, 0, 0, 0};
  std::string out;
  if (opt.json)
    out += fmt::format("{{\"mesh\": \"{}\", \"triangles\": {}, \"rule\": \"{}\", \"points\": [", opt.mesh, cm->triangle_count(),
                       to_string(cm->rule()));
  const auto f = [](double x) { return io::format_double(x); };
  // JSON has no infinity or NaN (a distance beyond double's range is inf): those as strings,
  // "inf", "-inf", "nan", which the JSON readers take and float() reads back.
  const auto j = [](double x) { return std::isfinite(x) ? io::format_double(x) : "\"" + io::format_double(x) + "\""; };
  for (std::size_t i = 0; i < n; ++i) {
    const ClosestPoint& r = res[i];
    ++sides[int(r.side)], ++stages[int(r.stage)];
    if (opt.json) {
      out += fmt::format(
          "{}{{\"distance\": {}, {}\"side\": \"{}\", \"triangle\": {}, \"point\": [{}, {}, {}], \"barycentric\": [{}, {}, {}]}}",
          i ? ", " : "", j(r.distance), opt.signed_first ? fmt::format("\"signed\": {}, ", j(r.signed_distance())) : "",
          to_string(r.side), r.triangle, j(r.point.x), j(r.point.y), j(r.point.z), j(r.barycentric[0]), j(r.barycentric[1]),
          j(r.barycentric[2]));
    } else {
      if (opt.signed_first) out += f(r.signed_distance()) + " ";
      out += fmt::format("{} {} {}\n", f(r.distance), to_string(r.side), r.triangle);
      if (out.size() > (1 << 16)) std::fwrite(out.data(), 1, out.size(), stdout), out.clear();
    }
  }
  if (opt.json)
    out += fmt::format("], \"count\": {}, \"inside\": {}, \"outside\": {}, \"surface\": {}}}\n", n, sides[1], sides[0], sides[2]);
  std::fwrite(out.data(), 1, out.size(), stdout);
  fmt::print(stderr,
             "{}: {} points: {} inside, {} outside, {} on the surface ({} triangles); decided by the double filter {}, "
             "rounding in rationals {}, candidates compared in rationals {}, searched in rationals {}\n",
             me, n, sides[1], sides[0], sides[2], cm->triangle_count(), stages[0], stages[1], stages[2], stages[3]);
  return 0;
}

}  // namespace

Run add_distance(CLI::App& app) {
  auto opt = std::make_shared<DistanceOptions>();
  auto* sub = app.add_subcommand("distance", "Distance from points to a mesh, exact: DIST SIDE TRI per point (the distance "
                                              "correctly rounded, the side, a nearest triangle)");
  sub->add_option("mesh", opt->mesh, "Mesh file (.off .obj .ply .stl); open meshes and soups too")->required();
  sub->add_option("points", opt->points, "Point file (x y z per line), or - for standard input")->required();
  sub->add_flag("--signed", opt->signed_first, "Print the signed distance first (negative inside, 0 on the surface)");
  sub->add_flag("--json", opt->json, "Print one JSON object with the closest points and barycentrics too");
  sub->add_option("--threads,-j", opt->threads, "Threads (0: all)")->capture_default_str();
  return [opt] { return run_distance(*opt); };
}

}  // namespace rayproof::cli
