// The measuring half of `rayproof bench intersect` (intersect_bench.h): rayproof timed on one thread,
// the peers run and compared pair by pair, the Open3D child process, the generated meshes and the
// sentences.
#include "scene/compare/intersect_bench.h"

#include <fmt/core.h>
#include <poll.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "methods/child_process.h"
#include "scene/watertight.h"

namespace rayproof::scene::compare {

namespace {

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

MeshArrays arrays_of(const mesh::Mesh& m) {
  return {VertexArray(m.vertices.empty() ? nullptr : &m.vertices[0].x, m.vertices.size()),
          IndexArray{m.triangles.empty() ? nullptr : m.triangles.front().data(), m.triangles.size()}};
}

/// A sheet of n x n squares in z = 0 over [0, n]^2 folded along x = k onto itself.
mesh::Mesh folded(int n, int k) {
  mesh::Mesh m;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) m.vertices.push_back({double(x > k ? 2 * k - x : x), double(y), 0.0});
  const auto at = [n](int x, int y) { return std::uint32_t(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      m.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
      m.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
    }
  return m;
}

// The child's program: reads the arrays, times the call alone, writes the pairs as int64 to the
// output file and one line "rayproof-open3d VERSION SECONDS COUNT" to its standard output.
constexpr const char* open3d_script = R"(import sys, time
try:
    import numpy as np
    import open3d as o3d
except Exception as e:
    print("rayproof-open3d-missing", type(e).__name__, str(e).replace("\n", " "))
    sys.exit(0)
v = np.fromfile(sys.argv[1], dtype=np.float64).reshape(-1, 3)
t = np.fromfile(sys.argv[2], dtype=np.int32).reshape(-1, 3)
m = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(v), o3d.utility.Vector3iVector(t))
best = None
for r in range(int(sys.argv[3])):
    t0 = time.process_time()
    p = m.get_self_intersecting_triangles()
    d = time.process_time() - t0
    best = d if best is None else min(best, d)
p = np.asarray(p, dtype=np.int64).reshape(-1, 2)
p.tofile(sys.argv[4])
print("rayproof-open3d", o3d.__version__, repr(best), len(p))
)";

/// The child's standard output up to its end, or false at the deadline.
bool read_to_end(int fd, std::string& out, proc::Clock::time_point deadline) {
  char buf[4096];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - proc::Clock::now()).count();
    if (left <= 0) return false;
    pollfd p{fd, POLLIN, 0};
    const int r = poll(&p, 1, int(std::min<long long>(left, 1000)));
    if (r < 0 && errno != EINTR) return true;
    if (r <= 0) continue;
    const ssize_t n = read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return true;
    out.append(buf, std::size_t(n));
  }
}

}  // namespace

mesh::Mesh joined(const mesh::Mesh& a, const mesh::Mesh& b) {
  mesh::Mesh m = a;
  const auto off = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) m.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
  return m;
}

mesh::Mesh moved(mesh::Mesh m, Vec3<double> d) {
  for (auto& v : m.vertices) v = v + d;
  return m;
}

mesh::Mesh moved_one_ulp(mesh::Mesh m) {
  for (auto& v : m.vertices) v.x = std::nextafter(v.x, HUGE_VAL);
  return m;
}

mesh::Mesh shifted_copy(const mesh::Mesh& m) {
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const auto& v : m.vertices)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], v[k]), hi[k] = std::max(hi[k], v[k]);
  if (m.vertices.empty()) return m;
  return moved(m, {0.3 * (hi[0] - lo[0]), 0.1 * (hi[1] - lo[1]), 0.05 * (hi[2] - lo[2])});
}

std::vector<NamedMesh> generated_intersect_meshes() {
  std::vector<NamedMesh> out;
  const mesh::Mesh s = bumpy_sphere(20000);
  out.push_back({"two overlapping spheres", joined(s, moved(s, {0.6, 0.2, 0.1}))});
  const mesh::Mesh small = bumpy_sphere(5000);
  out.push_back({"sphere + copy moved one ulp", joined(small, moved_one_ulp(small))});
  out.push_back({"folded sheet", folded(60, 25)});
  return out;
}

std::size_t pairs_missing_from(const std::vector<TrianglePair>& a, const std::vector<TrianglePair>& b) {
  std::size_t n = 0;
  for (const auto& p : a) n += !std::binary_search(b.begin(), b.end(), p);
  return n;
}

std::vector<TrianglePair> pairs_sharing_no_index(const mesh::Mesh& m, const std::vector<TrianglePair>& pairs) {
  std::vector<TrianglePair> out;
  for (const auto& p : pairs) {
    if (p.i == p.j) continue;
    bool shared = false;
    for (auto x : m.triangles[p.i])
      for (auto y : m.triangles[p.j]) shared = shared || x == y;
    if (!shared) out.push_back({p.i, p.j});
  }
  return out;
}

PeerPairs open3d_self_intersections(const std::string& python, const mesh::Mesh& m, int repeat) {
  PeerPairs out;
  static std::atomic<int> serial{0};
  const auto dir = std::filesystem::temp_directory_path();
  const std::string stem = fmt::format("rayproof-open3d-{}-{}", getpid(), serial++);
  const std::string vf = (dir / (stem + ".v")).string(), tf = (dir / (stem + ".t")).string(),
                    pf = (dir / (stem + ".p")).string();
  struct Cleanup {
    std::vector<std::string> files;
    ~Cleanup() {
      std::error_code ec;
      for (const auto& f : files) std::filesystem::remove(f, ec);
    }
  } cleanup{{vf, tf, pf}};
  {
    std::ofstream v(vf, std::ios::binary), t(tf, std::ios::binary);
    for (const auto& p : m.vertices) {
      const double xyz[3] = {p.x, p.y, p.z};
      v.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
    }
    for (const auto& f : m.triangles) {
      const std::int32_t ijk[3] = {std::int32_t(f[0]), std::int32_t(f[1]), std::int32_t(f[2])};
      t.write(reinterpret_cast<const char*>(ijk), sizeof ijk);
    }
    if (!v || !t) {
      out.note = fmt::format("could not write the mesh to {}", dir.string());
      return out;
    }
  }
  proc::Child ch;
  const std::string why =
      proc::spawn(python, {python, "-c", open3d_script, vf, tf, std::to_string(std::max(1, repeat)), pf}, {}, ch);
  if (!why.empty()) {
    out.note = fmt::format("not run: {}", why);
    return out;
  }
  proc::close_fd(ch.to);
  std::string text;
  const bool done = read_to_end(ch.from, text, proc::Clock::now() + std::chrono::minutes(10));
  const std::string ended = proc::end(ch, !done);
  if (!done) {
    out.note = "not run: the child took over 10 minutes (ended)";
    return out;
  }
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream w(line);
    std::string tag, version;
    if (!(w >> tag)) continue;
    if (tag == "rayproof-open3d-missing") {
      std::string error, message;
      w >> error;
      std::getline(w, message);
      out.note = fmt::format("not installed: {} cannot import open3d and numpy (Debian: python3-open3d; --python): {}:{}",
                             python, error, message);
      return out;
    }
    double seconds = 0;
    std::size_t count = 0;
    if (tag != "rayproof-open3d" || !(w >> version >> seconds >> count)) continue;
    std::ifstream p(pf, std::ios::binary);
    std::vector<std::int64_t> ij(2 * count);
    if (!p.read(reinterpret_cast<char*>(ij.data()), std::streamsize(ij.size() * sizeof(std::int64_t)))) break;
    for (std::size_t k = 0; k < count; ++k) {
      const auto a = std::uint32_t(ij[2 * k]), b = std::uint32_t(ij[2 * k + 1]);
      out.pairs.push_back({std::min(a, b), std::max(a, b)});
    }
    std::sort(out.pairs.begin(), out.pairs.end());
    out.pairs.erase(std::unique(out.pairs.begin(), out.pairs.end()), out.pairs.end());
    out.seconds = seconds;
    out.ran = true;
    out.note = "Open3D " + version;
    return out;
  }
  out.note = fmt::format("not run: the child {} without an answer", ended);
  return out;
}

namespace {

PeerRow compare(const char* name, const PeerPairs& peer, const std::vector<TrianglePair>& reference,
                bool restricted) {
  PeerRow r;
  r.peer = name;
  r.restricted = restricted;
  r.ran = peer.ran;
  r.note = peer.note;
  if (!peer.ran) return r;
  r.pairs = peer.pairs.size();
  r.reference = reference.size();
  r.missing = pairs_missing_from(reference, peer.pairs);
  r.extra = pairs_missing_from(peer.pairs, reference);
  r.seconds = peer.seconds;
  return r;
}

PeerRow skipped(const char* name, std::string why) {
  PeerRow r;
  r.peer = name;
  r.note = std::move(why);
  return r;
}

}  // namespace

IntersectRow self_intersect_row(const std::string& name, const mesh::Mesh& m, const IntersectBenchOptions& opt) {
  IntersectRow row;
  row.name = name;
  row.triangles = m.triangles.size();
  IntersectOptions one;
  one.threads = 1;
  const MeshArrays a = arrays_of(m);
  std::vector<TrianglePair> ours;
  row.seconds = HUGE_VAL;
  for (int r = 0; r < std::max(1, opt.repeat); ++r) {
    const double t0 = cpu_seconds();
    ours = self_intersections(a.vertices, a.indices, one);
    row.seconds = std::min(row.seconds, cpu_seconds() - t0);
  }
  row.pairs = ours.size();
  if (!opt.peers) return row;
  row.peers.push_back(compare("CGAL PMP Epick", cgal_self_intersections(m, false, opt.repeat), ours, false));
  if (m.triangles.size() <= opt.epeck_max)
    row.peers.push_back(compare("CGAL PMP Epeck", cgal_self_intersections(m, true, opt.repeat), ours, false));
  else
    row.peers.push_back(skipped("CGAL PMP Epeck", fmt::format("skipped: over {} triangles (Epeck is slow; --epeck-max)",
                                                              opt.epeck_max)));
  if (m.triangles.size() <= opt.open3d_max)
    row.peers.push_back(
        compare("Open3D", open3d_self_intersections(opt.python, m, opt.repeat), pairs_sharing_no_index(m, ours), true));
  else
    row.peers.push_back(skipped(
        "Open3D", fmt::format("skipped: over {} triangles (it tests every pair; --open3d-max)", opt.open3d_max)));
  return row;
}

IntersectRow contact_row(const std::string& name, const mesh::Mesh& a, const mesh::Mesh& b,
                         const IntersectBenchOptions& opt) {
  IntersectRow row;
  row.name = name;
  row.two = true;
  row.triangles = a.triangles.size();
  row.triangles2 = b.triangles.size();
  IntersectOptions one;
  one.threads = 1;
  std::vector<TrianglePair> ours;
  row.seconds = HUGE_VAL;
  for (int r = 0; r < std::max(1, opt.repeat); ++r) {
    const double t0 = cpu_seconds();
    ours = intersecting_pairs(arrays_of(a), arrays_of(b), one);
    row.seconds = std::min(row.seconds, cpu_seconds() - t0);
  }
  row.pairs = ours.size();
  if (opt.peers) row.peers.push_back(compare("FCL", fcl_contact_pairs(a, b, opt.repeat), ours, false));
  return row;
}

std::string time_ratio_text(double peer_seconds, double ours_seconds) {
  if (!(ours_seconds > 0) || !std::isfinite(peer_seconds)) return "n/a";
  return fmt::format("{:.2f}x", peer_seconds / ours_seconds);
}

std::string peer_sentence(const IntersectRow& row, const PeerRow& p) {
  if (!p.ran) return fmt::format("{}: {}.", p.peer, p.note);
  std::string s = p.peer + ": ";
  if (p.restricted)
    s += fmt::format("it skips pairs that share a vertex index, so it is compared with the {} of rayproof's {} pairs "
                     "that share none; ",
                     p.reference, row.pairs);
  if (p.missing == 0 && p.extra == 0)
    s += fmt::format("{} pairs, the same as rayproof's {}", p.pairs, p.reference);
  else
    s += fmt::format("{} pairs against rayproof's {}: {} of rayproof's missing, {} not in rayproof's exact set", p.pairs,
                     p.reference, p.missing, p.extra);
  const std::string ratio = time_ratio_text(p.seconds, row.seconds);
  if (ratio == "n/a") return s + "; no time ratio (rayproof's time is not positive).";
  s += fmt::format("; its time {} rayproof's", ratio);
  if (ratio == "1.00x") return s + " (the same to two digits).";
  return s + (ratio.compare(0, 2, "0.") == 0 ? " (rayproof slower)." : " (rayproof faster).");
}

}  // namespace rayproof::scene::compare
