/// rayproof intersect MESH [MESH2] [--count] [--json] [--classes] [--threads N]: the exact
/// self-intersections of one mesh, or the pairs of triangles of two meshes that share a point
/// (rayproof/scene/intersections.h, docs/intersect.md). One line per pair, `i j` (i < j; `i i` for a
/// zero-area triangle of one mesh), sorted; --classes adds the pair's class; --count prints the
/// number of pairs alone; --json one object. Errors (exit 2, one message): a missing or unreadable
/// file, a mesh without triangles, a NaN or infinite coordinate.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/mesh_input.h"
#include "mesh/mesh.h"
#include "rayproof/scene/intersections.h"

namespace rayproof::cli {

namespace {

struct IntersectOptionsCli {
  std::string mesh, mesh2;
  bool count = false, json = false, classes = false;
  int threads = 0;
};

MeshArrays arrays(const mesh::Mesh& m) {
  return {VertexArray(&m.vertices[0].x, m.vertices.size()), IndexArray{m.triangles.front().data(), m.triangles.size()}};
}

int run_intersect(const IntersectOptionsCli& opt) {
  const char* me = "rayproof intersect";
  const std::optional<mesh::Mesh> a = read_mesh_file(me, opt.mesh);
  if (!a) return 2;
  std::optional<mesh::Mesh> b;
  if (!opt.mesh2.empty() && !(b = read_mesh_file(me, opt.mesh2))) return 2;
  IntersectOptions io;
  io.threads = opt.threads, io.classes = opt.classes;
  std::vector<TrianglePair> pairs;
  try {
    pairs = b ? intersecting_pairs(arrays(*a), arrays(*b), io)
              : self_intersections(arrays(*a).vertices, arrays(*a).indices, io);
  } catch (const MeshInputError& e) {  // which mesh: the message says first or second
    fmt::print(stderr, "{}: {}: {}\n", me, b ? opt.mesh + " and " + opt.mesh2 : opt.mesh, e.what());
    return 2;
  }
  std::string out;
  if (opt.json) {
    out += fmt::format("{{\"meshes\": [\"{}\"{}], \"triangles\": [{}{}], \"pairs\": [", opt.mesh,
                       b ? fmt::format(", \"{}\"", opt.mesh2) : "", a->triangles.size(),
                       b ? fmt::format(", {}", b->triangles.size()) : "");
    if (!opt.count)
      for (std::size_t k = 0; k < pairs.size(); ++k)
        out += opt.classes ? fmt::format("{}[{}, {}, \"{}\"]", k ? ", " : "", pairs[k].i, pairs[k].j, to_string(pairs[k].cls))
                           : fmt::format("{}[{}, {}]", k ? ", " : "", pairs[k].i, pairs[k].j);
    out += fmt::format("], \"count\": {}}}\n", pairs.size());
  } else if (opt.count) {
    out = fmt::format("{}\n", pairs.size());
  } else {
    for (const TrianglePair& p : pairs) {
      out += opt.classes ? fmt::format("{} {} {}\n", p.i, p.j, to_string(p.cls)) : fmt::format("{} {}\n", p.i, p.j);
      if (out.size() > (1 << 16)) std::fwrite(out.data(), 1, out.size(), stdout), out.clear();
    }
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  std::size_t zero_area = 0;
  for (const TrianglePair& p : pairs) zero_area += !b && p.i == p.j;
  if (b)
    fmt::print(stderr, "{}: {} pairs of triangles meet ({} x {} triangles)\n", me, pairs.size(), a->triangles.size(),
               b->triangles.size());
  else
    fmt::print(stderr, "{}: {} pairs ({} of them a zero-area triangle alone) among {} triangles\n", me, pairs.size(),
               zero_area, a->triangles.size());
  return 0;
}

}  // namespace

Run add_intersect(CLI::App& app) {
  auto opt = std::make_shared<IntersectOptionsCli>();
  auto* sub = app.add_subcommand("intersect", "Exact self-intersections of a mesh (CGAL PMP's definition), or the pairs of "
                                               "triangles of two meshes that meet: `i j` per pair");
  sub->add_option("mesh", opt->mesh, "Mesh file (.off .obj .ply .stl); open meshes and soups too")->required();
  sub->add_option("mesh2", opt->mesh2, "A second mesh: the pairs (triangle of MESH, triangle of MESH2) that meet");
  sub->add_flag("--count", opt->count, "Print the number of pairs alone");
  sub->add_flag("--json", opt->json, "Print one JSON object (with --count: the count, no pairs)");
  sub->add_flag("--classes", opt->classes, "Add each pair's exact triangle/triangle class (docs/tritri.md)");
  sub->add_option("--threads,-j", opt->threads, "Threads (0: all)")->capture_default_str();
  return [opt] { return run_intersect(*opt); };
}

}  // namespace rayproof::cli
