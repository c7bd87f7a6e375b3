// CGAL PMP's self_intersections (Epick, Epeck) and FCL's mesh-mesh collision for `rayproof bench
// intersect` and bench/intersect_bench (intersect_compare.h). Compiled only with
// RAYPROOF_BUILD_BENCH=ON (the PMP header is most of a minute of compile); FCL only when the
// build found libfcl-dev (RAYPROOF_HAVE_FCL).
#include "scene/compare/intersect_compare.h"

#include <time.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#ifdef RAYPROOF_HAVE_FCL
#include <fcl/fcl.h>
#endif

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <memory>
#include <utility>

namespace rayproof::scene::compare {

namespace {

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

void sort_unique(std::vector<TrianglePair>& p) {
  std::sort(p.begin(), p.end());
  p.erase(std::unique(p.begin(), p.end()), p.end());
}

template <class K>
PeerPairs cgal_run(const mesh::Mesh& m, int repeat) {
  using SM = CGAL::Surface_mesh<typename K::Point_3>;
  PeerPairs out;
  SM sm;
  for (const auto& v : m.vertices) sm.add_vertex(typename K::Point_3(v.x, v.y, v.z));
  std::size_t refused = 0;
  for (const auto& t : m.triangles)
    refused += sm.add_face(typename SM::Vertex_index(t[0]), typename SM::Vertex_index(t[1]),
                           typename SM::Vertex_index(t[2])) == SM::null_face();
  if (refused) {
    out.note = std::to_string(refused) + " faces refused by Surface_mesh (not a manifold, oriented mesh)";
    return out;
  }
  out.seconds = 1e300;
  for (int r = 0; r < std::max(1, repeat); ++r) {
    std::vector<std::pair<typename SM::Face_index, typename SM::Face_index>> pairs;
    const double t0 = cpu_seconds();
    CGAL::Polygon_mesh_processing::self_intersections<CGAL::Sequential_tag>(sm, std::back_inserter(pairs));
    out.seconds = std::min(out.seconds, cpu_seconds() - t0);
    out.pairs.clear();
    for (auto [f, g] : pairs) {
      const auto a = std::uint32_t(f), b = std::uint32_t(g);
      out.pairs.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  sort_unique(out.pairs);
  out.ran = true;
  return out;
}

#ifdef RAYPROOF_HAVE_FCL
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> fcl_model(const mesh::Mesh& m) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> v;
  std::vector<fcl::Triangle> t;
  v.reserve(m.vertices.size());
  t.reserve(m.triangles.size());
  for (const auto& p : m.vertices) v.emplace_back(p.x, p.y, p.z);
  for (const auto& f : m.triangles) t.emplace_back(f[0], f[1], f[2]);
  model->beginModel();
  model->addSubModel(v, t);
  model->endModel();
  return model;
}
#endif

}  // namespace

PeerPairs cgal_self_intersections(const mesh::Mesh& m, bool epeck, int repeat) {
  return epeck ? cgal_run<CGAL::Exact_predicates_exact_constructions_kernel>(m, repeat)
               : cgal_run<CGAL::Exact_predicates_inexact_constructions_kernel>(m, repeat);
}

PeerPairs fcl_contact_pairs([[maybe_unused]] const mesh::Mesh& a, [[maybe_unused]] const mesh::Mesh& b,
                            [[maybe_unused]] int repeat) {
  PeerPairs out;
#ifdef RAYPROOF_HAVE_FCL
  out.seconds = 1e300;
  for (int r = 0; r < std::max(1, repeat); ++r) {
    const double t0 = cpu_seconds();
    fcl::CollisionObjectd oa(fcl_model(a)), ob(fcl_model(b));
    fcl::CollisionRequestd req(std::size_t(1) << 30, false);
    fcl::CollisionResultd res;
    fcl::collide(&oa, &ob, req, res);
    out.seconds = std::min(out.seconds, cpu_seconds() - t0);
    std::vector<fcl::Contactd> contacts;
    res.getContacts(contacts);
    out.pairs.clear();
    for (const auto& c : contacts) out.pairs.push_back({std::uint32_t(c.b1), std::uint32_t(c.b2)});
  }
  sort_unique(out.pairs);
  out.ran = true;
#else
  out.note = "not built in this build (libfcl-dev not found)";
#endif
  return out;
}

bool intersect_peers_built() { return true; }

}  // namespace rayproof::scene::compare
