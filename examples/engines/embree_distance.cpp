// Embree 3's rtcPointQuery as a distance function for `rayproof check --distance` (docs/check.md,
// "Distances"), as Embree's closest-point tutorial does it, in float throughout: the vertices and
// each query point rounded to float, a point-query callback that takes each candidate triangle's
// closest point by its Voronoi regions (vertex, edge or face) in float, keeps the nearest and
// shrinks the query radius to its distance. One thread (device "threads=1"): the same answers on
// every run. With --closest each distance is followed by that closest point and its triangle
// (`d x y z triangle`). Embree is float32: judge it with --distance-precision float.
//
//   rayproof check --distance 'embree=build/examples/embree_distance' --distance-precision float --mesh mesh.off
//   rayproof check --distance 'embree=build/examples/embree_distance --closest' --distance-precision float --mesh mesh.off
#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <string_view>

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

}  // namespace

int main(int argc, char** argv) {
  const bool closest = argc == 2 && std::string_view(argv[1]) == "--closest";
  if (argc > 1 && !closest) engine_example::fail("usage: embree_distance [--closest] (then the line protocol on stdin)");
  const engine_example::Mesh mesh = engine_example::read_mesh("rayproof-distance");
  std::vector<V3> vertices;
  for (const auto& v : mesh.vertices) vertices.push_back({float(v[0]), float(v[1]), float(v[2])});
  RTCDevice device = rtcNewDevice("threads=1");
  RTCScene scene = rtcNewScene(device);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<V3*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(V3), vertices.size()));
  std::copy(vertices.begin(), vertices.end(), vb);
  auto* ib = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(std::uint32_t), mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) ib[3 * i + k] = mesh.triangles[i][k];
  rtcSetGeometryPointQueryFunction(g, nearest_triangle);
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  engine_example::serve_batches([&](const std::vector<std::array<double, 3>>& points) {
    std::vector<std::string> answers;
    for (const auto& p : points) {
      Query q{&vertices, &mesh.triangles, {float(p[0]), float(p[1]), float(p[2])}};
      RTCPointQuery query;
      query.x = q.p.x, query.y = q.p.y, query.z = q.p.z, query.time = 0.f;
      query.radius = std::numeric_limits<float>::infinity();
      RTCPointQueryContext context;
      rtcInitPointQueryContext(&context);
      rtcPointQuery(scene, &query, &context, nullptr, &q);
      if (closest)
        answers.push_back(fmt::format("{} {} {} {} {}", double(std::sqrt(q.d2)), double(q.nearest.x),
                                      double(q.nearest.y), double(q.nearest.z), q.triangle));
      else
        answers.push_back(fmt::format("{}", double(std::sqrt(q.d2))));
    }
    return answers;
  });
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
}
