// STL reader, ASCII ("solid ... facet normal ... outer loop / vertex x y z ... endsolid") and
// binary (80-byte header, uint32 count, 50 bytes per triangle, little endian). A binary file is
// recognised by its size matching 84 + 50 n; a count that does not match the bytes present is an
// error before anything is allocated. Vertices with bit-identical coordinates are welded so that
// closed STL meshes share their vertices like the indexed formats. Hand-written: STL is small, and
// this keeps byte-located errors and the size check ahead of any allocation.
#include <cstring>
#include <unordered_map>

#include "mesh/mesh.h"
#include "mesh/reader_util.h"

namespace rayproof::mesh {
namespace {

struct Welder {
  Mesh& m;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> buckets;
  std::uint32_t add(Vec3<double> p) {
    p = {p.x + 0.0, p.y + 0.0, p.z + 0.0};  // -0 and +0 weld together
    std::uint64_t h = 1469598103934665603ull;
    for (int k = 0; k < 3; ++k) {
      std::uint64_t b;
      std::memcpy(&b, &p[k], 8);
      h = (h ^ b) * 1099511628211ull;
    }
    auto& bucket = buckets[h];
    for (std::uint32_t i : bucket)
      if (m.vertices[i] == p) return i;
    const auto i = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back(p);
    bucket.push_back(i);
    return i;
  }
};

Mesh read_binary(std::istream& in, const std::string& name, std::uint32_t n, std::int64_t size) {
  if (size >= 0 && static_cast<std::uint64_t>(size) != 84ull + 50ull * n)
    detail::fail_byte(name, 80, "binary STL header claims " + std::to_string(n) + " triangles (" +
                                    std::to_string(84ull + 50ull * n) + " bytes) but the file has " +
                                    std::to_string(size) + " bytes");
  Mesh m;
  Welder w{m, {}};
  m.triangles.reserve(std::min<std::uint64_t>(n, detail::kMaxReserve));
  unsigned char rec[50];
  for (std::uint32_t t = 0; t < n; ++t) {
    if (!in.read(reinterpret_cast<char*>(rec), 50))
      detail::fail_byte(name, 84ull + 50ull * t, "truncated: triangle " + std::to_string(t) + " of " + std::to_string(n) + " is incomplete");
    std::uint32_t v[3];
    for (int k = 0; k < 3; ++k) {
      double c[3];
      for (int j = 0; j < 3; ++j) {
        const unsigned char* b = rec + 12 + 12 * k + 4 * j;
        const std::uint32_t u = b[0] | (b[1] << 8) | (b[2] << 16) | (std::uint32_t(b[3]) << 24);
        float f;
        std::memcpy(&f, &u, 4);
        if (!std::isfinite(f)) detail::fail_byte(name, 84ull + 50ull * t + 12 + 12 * k + 4 * j, "coordinate is not finite");
        c[j] = f;
      }
      v[k] = w.add({c[0], c[1], c[2]});
    }
    m.triangles.push_back({v[0], v[1], v[2]});
  }
  return m;
}

Mesh read_ascii(std::istream& in, const std::string& name) {
  detail::LineReader lines(in, name, 0);
  std::vector<std::string_view> t;
  Mesh m;
  Welder w{m, {}};
  std::vector<std::uint32_t> loop;
  bool in_loop = false, in_facet = false, ended = false;
  lines.next_nonblank(t);  // "solid [name]"
  while (lines.next_nonblank(t)) {
    if (t[0] == "facet") {
      if (in_facet) lines.fail("'facet' inside a facet");
      in_facet = true;
    } else if (t[0] == "outer") {
      if (!in_facet || in_loop) lines.fail("'outer loop' outside a facet");
      in_loop = true;
      loop.clear();
    } else if (t[0] == "vertex") {
      if (!in_loop) lines.fail("'vertex' outside 'outer loop'");
      if (t.size() != 4) lines.fail("'vertex' needs 3 coordinates");
      double c[3];
      for (int k = 0; k < 3; ++k)
        if (!detail::parse_double(t[1 + k], c[k]) || !std::isfinite(c[k]))
          lines.fail("bad vertex coordinate " + detail::quote(t[1 + k]));
      loop.push_back(w.add({c[0], c[1], c[2]}));
    } else if (t[0] == "endloop") {
      if (!in_loop) lines.fail("'endloop' without 'outer loop'");
      if (loop.size() < 3) lines.fail("loop has " + std::to_string(loop.size()) + " vertices (need at least 3)");
      detail::add_fan(m, loop.data(), loop.size());
      in_loop = false;
    } else if (t[0] == "endfacet") {
      if (!in_facet || in_loop) lines.fail("'endfacet' without a complete facet");
      in_facet = false;
    } else if (t[0] == "endsolid") {
      if (in_facet) lines.fail("'endsolid' inside a facet");
      ended = true;
      break;
    } else {
      lines.fail("unexpected " + detail::quote(t[0]) + " in ASCII STL");
    }
  }
  if (!ended) lines.fail("unexpected end of file, expected 'endsolid'");
  return m;
}

}  // namespace

Mesh read_stl(std::istream& in, const std::string& name) {
  const std::int64_t size = detail::remaining_bytes(in);
  char head[84];
  in.read(head, 84);
  const auto got = in.gcount();
  const bool solid = got >= 5 && std::memcmp(head, "solid", 5) == 0;
  std::uint32_t n = 0;
  if (got == 84) {
    const auto* b = reinterpret_cast<const unsigned char*>(head + 80);
    n = b[0] | (b[1] << 8) | (b[2] << 16) | (std::uint32_t(b[3]) << 24);
  }
  const bool binary_size = got == 84 && size >= 0 && static_cast<std::uint64_t>(size) == 84ull + 50ull * n;
  if (!solid || binary_size) {
    if (got < 84) detail::fail_byte(name, static_cast<std::uint64_t>(got), "truncated binary STL header (84 bytes needed)");
    return read_binary(in, name, n, size);
  }
  in.clear();
  in.seekg(-got, std::ios::cur);
  return read_ascii(in, name);
}

}  // namespace rayproof::mesh
