// glTF 2.0 (.gltf with external or embedded data: URIs, .glb) through Debian's tinygltf
// (libtinygltf-dev, the shared library: it brings its own JSON parser and image code). tinygltf
// parses the file; this file walks the default scene's nodes and checks every index, offset and
// count against the buffers before it reads a byte, since a malformed file may claim anything.
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <istream>
#include <iterator>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "mesh/reader_util.h"

#if RAYPROOF_HAVE_TINYGLTF
#include <tiny_gltf.h>
#endif

namespace rayproof::mesh {

namespace {
[[noreturn]] void fail(const std::string& name, const std::string& what) { throw MeshError(name + ": " + what); }
}  // namespace

#if !RAYPROOF_HAVE_TINYGLTF

std::string gltf_reader_name() { return "none (rayproof was built without tinygltf)"; }

Mesh read_gltf(std::istream&, const std::string& name) {
  fail(name, "glTF needs rayproof built with tinygltf (Debian: libtinygltf-dev nlohmann-json3-dev)");
}

#else

std::string gltf_reader_name() { return "tinygltf " RAYPROOF_TINYGLTF_VERSION; }

namespace {

/// Largest file (and external buffer) read: tinygltf takes lengths as unsigned int.
constexpr std::uint64_t kMaxBytes = std::uint64_t{1} << 31;

/// tinygltf's messages end in newlines and may hold several lines: one line, "; "-separated.
std::string one_line(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\r') continue;
    if (c == '\n') {
      if (!out.empty() && out.back() != ' ') out += "; ";
      continue;
    }
    out += c;
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  return out.empty() ? std::string("unreadable glTF") : out;
}

// File access for external buffers and images: regular files only (never a FIFO or a device, which
// could block or never end), at most kMaxBytes, no path expansion, no writing.
bool file_exists(const std::string& path, void*) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}
std::string expand_path(const std::string& path, void*) { return path; }
bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    if (err) *err += "'" + path + "' is not a regular file\n";
    return false;
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size > kMaxBytes) {
    if (err) *err += "'" + path + "' is larger than 2 GiB or of unknown size\n";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  out->resize(static_cast<std::size_t>(size));
  if (!in || !in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size))) {
    if (err) *err += "cannot read '" + path + "'\n";
    return false;
  }
  return true;
}
bool no_writing(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "rayproof reads glTF, it does not write it\n";
  return false;
}
/// Images are not decoded: a mesh reader needs none of them.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

using Mat4 = std::array<double, 16>;  // column-major, as glTF stores it
constexpr Mat4 kIdentity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Mat4 mul(const Mat4& a, const Mat4& b) {
  Mat4 c{};
  for (int col = 0; col < 4; ++col)
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[std::size_t(k * 4 + row)] * b[std::size_t(col * 4 + k)];
      c[std::size_t(col * 4 + row)] = s;
    }
  return c;
}

Vec3<double> apply(const Mat4& m, double x, double y, double z) {
  return {m[0] * x + m[4] * y + m[8] * z + m[12], m[1] * x + m[5] * y + m[9] * z + m[13],
          m[2] * x + m[6] * y + m[10] * z + m[14]};
}

class Walker {
 public:
  Walker(const tinygltf::Model& model, const std::string& name) : m_(model), name_(name), seen_(model.nodes.size(), 0) {}

  Mesh run() {
    for (const auto& ext : m_.extensionsRequired) {
      const bool harmless = ext.rfind("KHR_materials_", 0) == 0 || ext.rfind("KHR_texture_", 0) == 0 ||
                            ext.rfind("EXT_texture_", 0) == 0 || ext == "KHR_lights_punctual";
      if (!harmless) fail(name_, "needs extension " + ext + " (extensionsRequired), which rayproof does not read");
    }
    int scene = m_.defaultScene;
    if (scene < 0 && !m_.scenes.empty()) scene = 0;
    if (scene >= int(m_.scenes.size())) fail(name_, "scene " + std::to_string(scene) + " does not exist");
    if (scene < 0) {
      // No scene: every mesh once, in its own coordinates.
      for (std::size_t i = 0; i < m_.meshes.size(); ++i) add_mesh(int(i), kIdentity);
    } else {
      for (const int n : m_.scenes[std::size_t(scene)].nodes) visit(n, kIdentity, "scenes[" + std::to_string(scene) + "]");
    }
    return std::move(out_);
  }

 private:
  const tinygltf::Model& m_;
  const std::string& name_;
  std::vector<char> seen_;
  Mesh out_;

  [[noreturn]] void bad(const std::string& where, const std::string& what) const { fail(name_, where + ": " + what); }

  Mat4 local(const tinygltf::Node& n, const std::string& where) const {
    if (!n.matrix.empty()) {
      if (n.matrix.size() != 16) bad(where, "matrix has " + std::to_string(n.matrix.size()) + " numbers, not 16");
      Mat4 m;
      std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
      return m;
    }
    if (!n.translation.empty() && n.translation.size() != 3) bad(where, "translation needs 3 numbers");
    if (!n.rotation.empty() && n.rotation.size() != 4) bad(where, "rotation needs 4 numbers (a quaternion)");
    if (!n.scale.empty() && n.scale.size() != 3) bad(where, "scale needs 3 numbers");
    Mat4 t = kIdentity, r = kIdentity, s = kIdentity;
    if (!n.translation.empty()) t[12] = n.translation[0], t[13] = n.translation[1], t[14] = n.translation[2];
    if (!n.rotation.empty()) {
      const double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
      r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
           2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
           2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
           0,                       0,                       0,                       1};
    }
    if (!n.scale.empty()) s[0] = n.scale[0], s[5] = n.scale[1], s[10] = n.scale[2];
    return mul(t, mul(r, s));
  }

  void visit(int node, const Mat4& parent, const std::string& from) {
    if (node < 0 || node >= int(m_.nodes.size())) bad(from, "node " + std::to_string(node) + " does not exist");
    const std::string where = "nodes[" + std::to_string(node) + "]";
    // Each node has one parent in glTF: a second visit is a cycle or a shared child, either malformed.
    if (seen_[std::size_t(node)]) bad(where, "reached twice (a cycle, or a node with two parents)");
    seen_[std::size_t(node)] = 1;
    const tinygltf::Node& n = m_.nodes[std::size_t(node)];
    const Mat4 world = mul(parent, local(n, where));
    if (n.mesh >= 0) {
      if (n.mesh >= int(m_.meshes.size())) bad(where, "mesh " + std::to_string(n.mesh) + " does not exist");
      add_mesh(n.mesh, world);
    }
    for (const int c : n.children) visit(c, world, where);
  }

  void add_mesh(int mesh, const Mat4& world) {
    const auto& prims = m_.meshes[std::size_t(mesh)].primitives;
    for (std::size_t p = 0; p < prims.size(); ++p)
      add_primitive(prims[p], "meshes[" + std::to_string(mesh) + "].primitives[" + std::to_string(p) + "]", world);
  }

  /// The first byte of accessor `index` and its stride, after checking that `count` elements of
  /// `size` bytes lie inside its buffer view, and the view inside its buffer.
  const unsigned char* bytes(int index, std::size_t size, std::size_t& stride, const std::string& where) const {
    if (index < 0 || index >= int(m_.accessors.size())) bad(where, "accessor " + std::to_string(index) + " does not exist");
    const std::string at = "accessors[" + std::to_string(index) + "]";
    const tinygltf::Accessor& a = m_.accessors[std::size_t(index)];
    if (a.sparse.isSparse) bad(at, "sparse accessors are not read");
    if (a.bufferView < 0 || a.bufferView >= int(m_.bufferViews.size()))
      bad(at, a.bufferView < 0 ? std::string("no bufferView (all zeros) is not read")
                               : "bufferView " + std::to_string(a.bufferView) + " does not exist");
    const std::string vat = "bufferViews[" + std::to_string(a.bufferView) + "]";
    const tinygltf::BufferView& v = m_.bufferViews[std::size_t(a.bufferView)];
    if (v.buffer < 0 || v.buffer >= int(m_.buffers.size())) bad(vat, "buffer " + std::to_string(v.buffer) + " does not exist");
    const auto& data = m_.buffers[std::size_t(v.buffer)].data;
    const std::uint64_t view_end = std::uint64_t(v.byteOffset) + std::uint64_t(v.byteLength);
    if (v.byteOffset > kMaxBytes || v.byteLength > kMaxBytes || view_end > data.size())
      bad(vat, "bytes " + std::to_string(v.byteOffset) + " to " + std::to_string(view_end) + " lie beyond buffers[" +
                   std::to_string(v.buffer) + "], which holds " + std::to_string(data.size()) + " bytes");
    stride = v.byteStride ? v.byteStride : size;
    if (stride < size || stride > 252) bad(vat, "byteStride " + std::to_string(v.byteStride) + " does not fit the accessor");
    if (a.count > 0) {
      if (a.byteOffset > kMaxBytes || a.count > kMaxBytes) bad(at, "offset or count beyond any buffer");
      const std::uint64_t end = std::uint64_t(a.byteOffset) + std::uint64_t(stride) * (a.count - 1) + size;
      if (end > v.byteLength)
        bad(at, std::to_string(a.count) + " elements need " + std::to_string(end) + " bytes of " + vat + ", which has " +
                    std::to_string(v.byteLength));
    }
    return data.data() + v.byteOffset + (a.count > 0 ? a.byteOffset : 0);
  }

  void add_primitive(const tinygltf::Primitive& p, const std::string& where, const Mat4& world) {
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES) {
      static const char* const kModes[] = {"points", "lines", "line loop", "line strip", "triangles", "triangle strip",
                                           "triangle fan"};
      const std::string what = mode <= 6 ? kModes[mode] : "unknown";
      bad(where, "mode " + std::to_string(mode) + " (" + what +
                     ") is not a triangle list; rayproof reads triangle primitives (mode 4) only");
    }
    const auto pos = p.attributes.find("POSITION");
    if (pos == p.attributes.end()) bad(where, "no POSITION attribute");
    const tinygltf::Accessor* a = pos->second >= 0 && pos->second < int(m_.accessors.size())
                                      ? &m_.accessors[std::size_t(pos->second)] : nullptr;
    if (a && (a->type != TINYGLTF_TYPE_VEC3 || a->componentType != TINYGLTF_COMPONENT_TYPE_FLOAT))
      bad("accessors[" + std::to_string(pos->second) + "]", "POSITION must be VEC3 of FLOAT (5126)");
    std::size_t stride = 0;
    const unsigned char* src = bytes(pos->second, 12, stride, where + ".attributes.POSITION");
    const std::size_t count = a->count;
    const std::size_t base = out_.vertices.size();
    if (base + count > std::size_t{0xFFFFFFFFu}) bad(where, "more than 2^32 - 1 vertices in the file");
    for (std::size_t k = 0; k < count; ++k) {
      float f[3];
      std::memcpy(f, src + k * stride, 12);
      const Vec3<double> v = apply(world, f[0], f[1], f[2]);
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        bad("accessors[" + std::to_string(pos->second) + "]", "vertex " + std::to_string(k) + " is not finite" +
                                                                  (std::isfinite(f[0] + f[1] + f[2]) ? " after the node transform" : ""));
      out_.vertices.push_back(v);
    }
    if (p.indices < 0) {
      if (count % 3) bad(where, std::to_string(count) + " vertices without indices: not a multiple of 3");
      for (std::size_t k = 0; k < count; k += 3)
        out_.triangles.push_back({std::uint32_t(base + k), std::uint32_t(base + k + 1), std::uint32_t(base + k + 2)});
      return;
    }
    if (p.indices >= int(m_.accessors.size())) bad(where, "indices accessor " + std::to_string(p.indices) + " does not exist");
    const std::string iat = "accessors[" + std::to_string(p.indices) + "]";
    const tinygltf::Accessor& ia = m_.accessors[std::size_t(p.indices)];
    std::size_t size = 0;
    switch (ia.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: size = 1; break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: size = 2; break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: size = 4; break;
      default: bad(iat, "indices must be unsigned bytes, shorts or ints (componentType 5121, 5123, 5125)");
    }
    if (ia.type != TINYGLTF_TYPE_SCALAR) bad(iat, "indices must be SCALAR");
    if (ia.count % 3) bad(iat, std::to_string(ia.count) + " indices: not a multiple of 3");
    const unsigned char* is = bytes(p.indices, size, stride, where + ".indices");
    for (std::size_t k = 0; k < ia.count; k += 3) {
      std::array<std::uint32_t, 3> t{};
      for (std::size_t c = 0; c < 3; ++c) {
        const unsigned char* e = is + (k + c) * stride;
        std::uint32_t i = 0;
        if (size == 1) i = e[0];
        else if (size == 2) i = std::uint32_t(e[0]) | std::uint32_t(e[1]) << 8;
        else i = std::uint32_t(e[0]) | std::uint32_t(e[1]) << 8 | std::uint32_t(e[2]) << 16 | std::uint32_t(e[3]) << 24;
        if (i >= count) bad(iat, "index " + std::to_string(i) + " (element " + std::to_string(k + c) + ") beyond the " +
                                     std::to_string(count) + " vertices");
        t[c] = std::uint32_t(base + i);
      }
      out_.triangles.push_back(t);
    }
  }
};

}  // namespace

Mesh read_gltf(std::istream& in, const std::string& name) {
  const std::int64_t left = detail::remaining_bytes(in);
  if (left > std::int64_t(kMaxBytes)) fail(name, "larger than 2 GiB");
  std::string bytes;
  {
    char buf[1 << 16];
    while (in.read(buf, sizeof buf) || in.gcount() > 0) {
      bytes.append(buf, std::size_t(in.gcount()));
      if (bytes.size() > kMaxBytes) fail(name, "larger than 2 GiB");
    }
  }
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  loader.SetFsCallbacks({file_exists, expand_path, read_whole_file, no_writing, nullptr});
  tinygltf::Model model;
  std::string err, warn;
  const std::string base = std::filesystem::path(name).parent_path().string();
  // The magic decides, not the extension: a .gltf that holds binary glTF is read as such.
  const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                                       reinterpret_cast<const unsigned char*>(bytes.data()),
                                                       static_cast<unsigned int>(bytes.size()), base)
                         : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                                      static_cast<unsigned int>(bytes.size()), base);
  if (!ok) fail(name, std::string(binary ? "binary glTF" : "glTF") + " (tinygltf): " + one_line(err.empty() ? warn : err));
  return Walker(model, name).run();
}

#endif

}  // namespace rayproof::mesh
