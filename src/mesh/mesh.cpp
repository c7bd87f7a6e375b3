// Mesh reading front door, shared reader helpers and the writers.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ostream>

#include "mesh/mesh.h"
#include "mesh/reader_util.h"

namespace rayproof::mesh {

VertexBounds vertex_bounds(const Mesh& m, bool used_only) {
  VertexBounds b{used_only ? m.vertices[m.triangles.at(0)[0]] : m.vertices.at(0), {}};
  b.hi = b.lo;
  auto add = [&](const Vec3<double>& p) {
    b.lo = {std::min(b.lo.x, p.x), std::min(b.lo.y, p.y), std::min(b.lo.z, p.z)};
    b.hi = {std::max(b.hi.x, p.x), std::max(b.hi.y, p.y), std::max(b.hi.z, p.z)};
  };
  if (used_only) {
    for (const auto& t : m.triangles)
      for (std::uint32_t v : t) add(m.vertices[v]);
  } else {
    for (const auto& p : m.vertices) add(p);
  }
  return b;
}
namespace detail {

std::string quote(std::string_view tok) {
  constexpr std::size_t kMax = 40;
  return "'" + std::string(tok.substr(0, kMax)) + (tok.size() > kMax ? "...'" : "'");
}

void fail_line(const std::string& name, std::size_t line, const std::string& what) {
  throw MeshError(name + ":" + std::to_string(line) + ": " + what);
}
void fail_byte(const std::string& name, std::uint64_t byte, const std::string& what) {
  throw MeshError(name + ": byte " + std::to_string(byte) + ": " + what);
}

bool LineReader::next(std::vector<std::string_view>& tokens) {
  tokens.clear();
  buf_.clear();
  // Reads one line by hand so that an absurdly long line is refused before it is stored whole.
  std::streambuf* sb = in_.rdbuf();
  bool any = false;
  for (;;) {
    const int c = sb->sbumpc();
    if (c == std::char_traits<char>::eof()) break;
    any = true;
    if (c == '\n') break;
    if (buf_.size() >= kMaxLine) fail_line(name_, line_ + 1, "line longer than " + std::to_string(kMaxLine) + " bytes");
    buf_.push_back(static_cast<char>(c));
  }
  if (!any) return false;
  ++line_;
  std::string_view s(buf_);
  if (comment_) {
    const auto k = s.find(comment_);
    if (k != std::string_view::npos) s = s.substr(0, k);
  }
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    std::size_t j = i;
    while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
    if (j > i) tokens.push_back(s.substr(i, j - i));
    i = j;
  }
  return true;
}

bool LineReader::next_nonblank(std::vector<std::string_view>& tokens) {
  while (next(tokens))
    if (!tokens.empty()) return true;
  return false;
}

bool TokenReader::next(std::string_view& tok) {
  while (pos_ >= toks_.size()) {
    if (!lines_.next(toks_)) return false;
    pos_ = 0;
  }
  tok = toks_[pos_++];
  return true;
}

std::string_view TokenReader::need(const char* what) {
  std::string_view t;
  if (!next(t)) lines_.fail(std::string("unexpected end of file, expected ") + what);
  return t;
}

double TokenReader::need_double(const char* what) {
  const std::string_view t = need(what);
  double v;
  if (!parse_double(t, v)) lines_.fail("expected " + std::string(what) + ", got " + detail::quote(t));
  if (!std::isfinite(v)) lines_.fail(std::string(what) + " is not finite: " + detail::quote(t));
  return v;
}

std::uint64_t TokenReader::need_uint(const char* what) {
  const std::string_view t = need(what);
  std::uint64_t v;
  if (!parse_uint(t, v)) lines_.fail("expected " + std::string(what) + " (a non-negative integer), got " + detail::quote(t));
  return v;
}

bool parse_double(std::string_view tok, double& out) {
  if (tok.empty() || tok.size() > 512) return false;
  char buf[513];
  std::memcpy(buf, tok.data(), tok.size());
  buf[tok.size()] = '\0';
  char* end = nullptr;
  out = std::strtod(buf, &end);
  return end == buf + tok.size();
}

bool parse_uint(std::string_view tok, std::uint64_t& out) {
  if (tok.empty() || tok[0] == '+' || tok[0] == '-') return false;
  const auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && p == tok.data() + tok.size();
}

bool parse_int(std::string_view tok, std::int64_t& out) {
  if (tok.empty() || tok[0] == '+') return false;
  const auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && p == tok.data() + tok.size();
}

void add_fan(Mesh& m, const std::uint32_t* idx, std::size_t n) {
  for (std::size_t k = 1; k + 1 < n; ++k) m.triangles.push_back({idx[0], idx[k], idx[k + 1]});
}

std::int64_t remaining_bytes(std::istream& in) {
  const auto here = in.tellg();
  if (here < 0) return -1;
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  in.seekg(here);
  if (end < 0) return -1;
  return static_cast<std::int64_t>(end - here);
}

}  // namespace detail

MeshFormat format_of(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".off") return MeshFormat::off;
  if (ext == ".obj") return MeshFormat::obj;
  if (ext == ".ply") return MeshFormat::ply;
  if (ext == ".stl") return MeshFormat::stl;
  if (ext == ".gltf" || ext == ".glb") return MeshFormat::gltf;
  throw MeshError(path + ": unknown mesh format '" + ext + "' (expected .off, .obj, .ply, .stl, .gltf or .glb)");
}

bool is_mesh_path(const std::string& path) {
  try {
    (void)format_of(path);
    return true;
  } catch (const MeshError&) {
    return false;
  }
}

Mesh read_mesh(std::istream& in, MeshFormat f, const std::string& name) {
  switch (f) {
    case MeshFormat::off: return read_off(in, name);
    case MeshFormat::obj: return read_obj(in, name);
    case MeshFormat::ply: return read_ply(in, name);
    case MeshFormat::gltf: return read_gltf(in, name);
    case MeshFormat::stl: break;
  }
  return read_stl(in, name);
}

std::string gltf_reader_name();  // gltf.cpp

std::string reader_name(MeshFormat f) {
  switch (f) {
    case MeshFormat::off: return "rayproof's OFF reader";
    case MeshFormat::obj: return "rayproof's OBJ reader";
    case MeshFormat::ply: return "rayproof's PLY reader";
    case MeshFormat::gltf: return gltf_reader_name();
    case MeshFormat::stl: break;
  }
  return "rayproof's STL reader";
}

Mesh read_mesh(const std::string& path) {
  const MeshFormat f = format_of(path);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw MeshError(path + ": no such file");
  if (std::filesystem::is_directory(path, ec)) throw MeshError(path + ": is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError(path + ": cannot open (" + std::strerror(errno) + ")");
  return read_mesh(in, f, path);
}

void write_off(std::ostream& out, const Mesh& m) {
  out << "OFF\n" << m.vertices.size() << ' ' << m.triangles.size() << " 0\n";
  char buf[128];
  for (const auto& v : m.vertices) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", v.x, v.y, v.z);
    out << buf;
  }
  for (const auto& t : m.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
}

void write_stl_binary(std::ostream& out, const Mesh& m) {
  char header[80] = "rayproof binary STL";
  out.write(header, 80);
  const auto n = static_cast<std::uint32_t>(m.triangles.size());
  auto put32 = [&](std::uint32_t v) {
    const unsigned char b[4] = {static_cast<unsigned char>(v), static_cast<unsigned char>(v >> 8),
                                static_cast<unsigned char>(v >> 16), static_cast<unsigned char>(v >> 24)};
    out.write(reinterpret_cast<const char*>(b), 4);
  };
  auto putf = [&](double d) {
    const float f = static_cast<float>(d);
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    put32(u);
  };
  put32(n);
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) putf(0.0);
    for (int k = 0; k < 3; ++k) {
      const auto& v = m.vertices[t[k]];
      putf(v.x), putf(v.y), putf(v.z);
    }
    out.write("\0\0", 2);
  }
}

}  // namespace rayproof::mesh
