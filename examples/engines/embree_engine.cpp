// Embree 3 as the judged function of `rayproof check` (docs/check.md), in float throughout as
// Embree takes its input: the vertices rounded to float, and each query point or ray too. One
// thread (device "threads=1"): the same answers on every run. One program, three modes:
//
//   embree_engine distance: rtcPointQuery as a distance function (`check --distance`), as Embree's
//     closest-point tutorial does it: a point-query callback that takes each candidate triangle's
//     closest point by its Voronoi regions (vertex, edge or face) in float, keeps the nearest and
//     shrinks the query radius to its distance;
//   embree_engine closest: the same query, each distance followed by that closest point and its
//     triangle (`d x y z triangle`, `check --distance`);
//   embree_engine crossings: every hit of a ray (`check --crossings`): rtcIntersect1 with an
//     intersection filter that records each hit Embree offers (t > 0, primID) and rejects it
//     (valid[0] = 0), so that traversal goes on to the next; the hits sorted by t. Embree reports
//     a hit per triangle: where the ray crosses a shared edge or vertex it may report each
//     triangle there, or none. `crossings --robust` sets RTC_SCENE_FLAG_ROBUST on the scene (Embree's
//     watertight triangle test instead of its faster one).
//
// Embree is float32: judge it with --distance-precision float or --crossings-precision float.
//
//   rayproof check --distance 'embree=build/examples/embree_engine distance' --distance-precision float --mesh mesh.off
//   rayproof check --distance 'embree=build/examples/embree_engine closest' --distance-precision float --mesh mesh.off
//   rayproof check --crossings 'embree=build/examples/embree_engine crossings' --crossings-precision float --mesh mesh.off
//   rayproof check --crossings 'embree=build/examples/embree_engine crossings --robust' --crossings-precision float --mesh mesh.off
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>
#include <utility>

#include "line_protocol.h"

namespace {

struct V3 {
  float x, y, z;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator*(V3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// The point of triangle abc nearest p: which vertex, edge or the face's interior holds it,
/// from the signs of dot products (the textbook region test), then that feature's nearest point.
V3 closest_on_triangle(V3 p, V3 a, V3 b, V3 c) {
  const V3 ab = b - a, ac = c - a;
  const float pa_ab = dot(p - a, ab), pa_ac = dot(p - a, ac);
  if (pa_ab <= 0 && pa_ac <= 0) return a;
  const float pb_ab = dot(p - b, ab), pb_ac = dot(p - b, ac);
  if (pb_ab >= 0 && pb_ac <= pb_ab) return b;
  const float pc_ab = dot(p - c, ab), pc_ac = dot(p - c, ac);
  if (pc_ac >= 0 && pc_ab <= pc_ac) return c;
  const float on_ab = pa_ab * pb_ac - pb_ab * pa_ac;
  if (on_ab <= 0 && pa_ab >= 0 && pb_ab <= 0) return a + ab * (pa_ab / (pa_ab - pb_ab));
  const float on_ac = pc_ab * pa_ac - pa_ab * pc_ac;
  if (on_ac <= 0 && pa_ac >= 0 && pc_ac <= 0) return a + ac * (pa_ac / (pa_ac - pc_ac));
  const float on_bc = pb_ab * pc_ac - pc_ab * pb_ac;
  if (on_bc <= 0 && pb_ac - pb_ab >= 0 && pc_ab - pc_ac >= 0)
    return b + (c - b) * ((pb_ac - pb_ab) / ((pb_ac - pb_ab) + (pc_ab - pc_ac)));
  const float scale = 1 / (on_ab + on_ac + on_bc);
  return a + ab * (on_ac * scale) + ac * (on_ab * scale);
}

struct Query {
  const std::vector<V3>* vertices;
  const std::vector<std::array<std::uint32_t, 3>>* triangles;
  V3 p;
  float d2 = std::numeric_limits<float>::infinity();
  V3 nearest{0, 0, 0};
  std::int64_t triangle = -1;
};

bool nearest_triangle(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<Query*>(args->userPtr);
  const auto& t = (*q->triangles)[args->primID];
  const std::vector<V3>& v = *q->vertices;
  const V3 x = closest_on_triangle(q->p, v[t[0]], v[t[1]], v[t[2]]);
  const V3 d = q->p - x;
  const float d2 = dot(d, d);
  if (!(d2 < q->d2)) return false;
  q->d2 = d2;
  q->nearest = x;
  q->triangle = args->primID;
  args->query->radius = std::sqrt(d2);
  return true;
}

/// The mesh as an Embree scene of one triangle geometry, its vertices rounded to float, with
/// `point_query` as its point-query callback or `filter` as its intersection filter (or null), and
/// RTC_SCENE_FLAG_ROBUST if `robust`.
struct Scene {
  RTCDevice device = rtcNewDevice("threads=1");
  RTCScene scene = rtcNewScene(device);
  std::vector<V3> vertices;

  Scene(const engine_example::Mesh& mesh, RTCPointQueryFunction point_query, RTCFilterFunctionN filter,
        bool robust = false) {
    if (robust) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    for (const auto& v : mesh.vertices) vertices.push_back({float(v[0]), float(v[1]), float(v[2])});
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<V3*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(V3), vertices.size()));
    std::copy(vertices.begin(), vertices.end(), vb);
    auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), mesh.triangles.size()));
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) ib[3 * i + k] = mesh.triangles[i][k];
    if (point_query) rtcSetGeometryPointQueryFunction(g, point_query);
    if (filter) rtcSetGeometryIntersectFilterFunction(g, filter);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
  }
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;
  ~Scene() {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
};

void distance(bool closest) {
  const engine_example::Mesh mesh = engine_example::read_mesh("rayproof-distance");
  const Scene s(mesh, nearest_triangle, nullptr);
  engine_example::serve_batches([&](const std::vector<std::array<double, 3>>& points) {
    std::vector<std::string> answers;
    for (const auto& p : points) {
      Query q{&s.vertices, &mesh.triangles, {float(p[0]), float(p[1]), float(p[2])}};
      RTCPointQuery query;
      query.x = q.p.x, query.y = q.p.y, query.z = q.p.z, query.time = 0.f;
      query.radius = std::numeric_limits<float>::infinity();
      RTCPointQueryContext context;
      rtcInitPointQueryContext(&context);
      rtcPointQuery(s.scene, &query, &context, nullptr, &q);
      if (closest)
        answers.push_back(fmt::format("{} {} {} {} {}", double(std::sqrt(q.d2)), double(q.nearest.x),
                                      double(q.nearest.y), double(q.nearest.z), q.triangle));
      else
        answers.push_back(fmt::format("{}", double(std::sqrt(q.d2))));
    }
    return answers;
  });
}

struct Hit {
  float t;
  unsigned triangle;
};

/// Embree's intersection context with the current ray's hits after it: the filter below receives
/// the context's address and finds them there.
struct HitsContext {
  RTCIntersectContext context;
  std::vector<Hit>* hits;
};

void record_and_reject(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<HitsContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const float t = RTCRayN_tfar(args->ray, args->N, i);
    if (t > 0) c->hits->push_back({t, RTCHitN_primID(args->hit, args->N, i)});
    args->valid[i] = 0;  // rejected: Embree goes on looking for hits beyond it
  }
}

/// Every hit of each ray, for `check --crossings`: `k t1 triangle1 ... tk trianglek`, by t.
void crossings(bool robust) {
  const engine_example::Mesh mesh = engine_example::read_mesh("rayproof-crossings");
  const Scene s(mesh, nullptr, record_and_reject, robust);
  engine_example::serve_ray_batches([&](const std::vector<std::array<double, 6>>& rays) {
    std::vector<std::string> answers;
    for (const auto& v : rays) {
      std::vector<Hit> hits;
      HitsContext c{{}, &hits};
      rtcInitIntersectContext(&c.context);
      RTCRayHit rh{};
      rh.ray.org_x = float(v[0]), rh.ray.org_y = float(v[1]), rh.ray.org_z = float(v[2]);
      rh.ray.dir_x = float(v[3]), rh.ray.dir_y = float(v[4]), rh.ray.dir_z = float(v[5]);
      rh.ray.tnear = 0.f;
      rh.ray.tfar = std::numeric_limits<float>::infinity();
      rh.ray.mask = 0xFFFFFFFFu;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(s.scene, &c.context, &rh);
      std::sort(hits.begin(), hits.end(),
                [](const Hit& a, const Hit& b) { return a.t < b.t || (a.t == b.t && a.triangle < b.triangle); });
      std::string answer = fmt::format("{}", hits.size());
      for (const Hit& h : hits) answer += fmt::format(" {} {}", double(h.t), h.triangle);
      answers.push_back(std::move(answer));
    }
    return answers;
  });
}

}  // namespace

int main(int argc, char** argv) {
  const std::string_view what = argc >= 2 ? argv[1] : "";
  const bool robust = argc == 3 && std::string_view(argv[2]) == "--robust";
  if (argc == 2 && (what == "distance" || what == "closest")) distance(what == "closest");
  else if (what == "crossings" && (argc == 2 || robust)) crossings(robust);
  else
    engine_example::fail(
        "usage: embree_engine distance|closest|crossings [--robust] (then the line protocol on stdin)");
}
