#pragma once
/// `rayproof cast MESH RAYS --query crossings [--touches]`: each ray's crossings of a triangle mesh,
/// once each, with direction (rayproof::ExactMesh::ray_crossings; docs/contains.md, "Crossings").
#include <string>

namespace rayproof::cli {

struct CastCrossingsArgs {
  std::string mesh, rays;
  double tmin = 0, tmax = 0;
  bool touches = false, verbose = false;
  int threads = 0;
};

/// One line per ray: `N t:in|out ...` (N crossings in t order), with --touches then
/// `| M t:CLASS ...` (CLASS edge, vertex or interior; a coplanar touch as `t..t2:coplanar`);
/// `invalid` for a ray with a NaN or infinite component or d = 0, `error` for an unreadable line.
/// Exit 0, 1 when a line could not be read, 2 when the mesh or ray file cannot be.
int run_cast_crossings(const CastCrossingsArgs& a);

}  // namespace rayproof::cli
