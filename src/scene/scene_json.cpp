// JSON scene descriptions (nlohmann-json). Every key is checked: an unknown key or a value of the
// wrong shape is an error naming the file and the JSON path ("scene.json: spheres[1].radius: ...").
//
// {
//   "camera": {"type": "perspective", "eye": [x,y,z], "target": [x,y,z], "up": [0,1,0],
//              "fov_y_degrees": 45, "width": 320, "height": 240},
//          or {"type": "orthographic", ..., "half_width": 2, "half_height": 1.5},
//   "meshes": [{"file": "bunny.off", "scale": 2 or [sx,sy,sz], "rotate_axis": [0,1,0],
//               "rotate_degrees": 30, "translate": [x,y,z]}   (scale, then rotate, then translate)
//              or {"file": ..., "matrix": [[4 numbers] x 4]}],   (row-major world_from_object)
//   "spheres": [{"center": [..], "radius": r}], "ellipsoids": [{"center": [..], "semi_axes": [..]}],
//   "disks": [{"center": [..], "normal": [..], "radius": r}], "boxes": [{"lo": [..], "hi": [..]}],
//   "lights": [{"type": "disk", "center": [..], "normal": [..], "radius": r, "emission": [r,g,b]}]
// }
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>

#include "scene/scene.h"

namespace rayproof::scene {
namespace {

using nlohmann::json;

/// nlohmann's message, cut short: it quotes the last token read, which can be a megabyte long.
std::string short_what(const std::exception& e) {
  const std::string w = e.what();
  return w.size() > 200 ? w.substr(0, 200) + "..." : w;
}

struct Ctx {
  const std::string& name;
  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw SceneError(name + ": " + path + ": " + what);
  }
  void keys(const json& j, const std::string& path, std::set<std::string> allowed) const {
    if (!j.is_object()) fail(path, "expected an object");
    for (const auto& [k, v] : j.items())
      if (!allowed.count(k)) fail(path, "unknown key '" + k + "'");
  }
  double num(const json& j, const std::string& path) const {
    if (!j.is_number()) fail(path, "expected a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(path, "not finite");
    return v;
  }
  double num(const json& o, const char* key, const std::string& path, std::optional<double> def = {}) const {
    if (!o.contains(key)) {
      if (def) return *def;
      fail(path, std::string("missing '") + key + "'");
    }
    return num(o[key], path + "." + key);
  }
  Vec3<double> vec(const json& o, const char* key, const std::string& path, std::optional<Vec3<double>> def = {}) const {
    const std::string p = path + "." + key;
    if (!o.contains(key)) {
      if (def) return *def;
      fail(path, std::string("missing '") + key + "'");
    }
    const json& j = o[key];
    if (!j.is_array() || j.size() != 3) fail(p, "expected [x, y, z]");
    return {num(j[0], p + "[0]"), num(j[1], p + "[1]"), num(j[2], p + "[2]")};
  }
  std::string str(const json& o, const char* key, const std::string& path, const std::string& def) const {
    if (!o.contains(key)) return def;
    if (!o[key].is_string()) fail(path + "." + key, "expected a string");
    return o[key].get<std::string>();
  }
  int dim(const json& o, const char* key, const std::string& path, int def) const {
    if (!o.contains(key)) return def;
    const json& j = o[key];
    if (!j.is_number_integer() || j.get<long long>() < 1 || j.get<long long>() > 16384)
      fail(path + "." + key, "expected an integer in [1, 16384]");
    return j.get<int>();
  }
};

Transform<double> mesh_transform(const Ctx& c, const json& j, const std::string& p) {
  Transform<double> t;
  if (j.contains("matrix")) {
    const json& m = j["matrix"];
    if (!m.is_array() || m.size() != 4) c.fail(p + ".matrix", "expected 4 rows of 4 numbers");
    for (int r = 0; r < 4; ++r) {
      if (!m[r].is_array() || m[r].size() != 4) c.fail(p + ".matrix", "expected 4 rows of 4 numbers");
      for (int k = 0; k < 4; ++k) t.m[r][k] = c.num(m[r][k], p + ".matrix[" + std::to_string(r) + "][" + std::to_string(k) + "]");
    }
    return t;
  }
  Vec3<double> s{1, 1, 1};
  if (j.contains("scale")) s = j["scale"].is_number() ? Vec3<double>{1, 1, 1} * c.num(j["scale"], p + ".scale") : c.vec(j, "scale", p);
  const Vec3<double> axis = c.vec(j, "rotate_axis", p, Vec3<double>{0, 1, 0});
  const double deg = c.num(j, "rotate_degrees", p, 0.0);
  const Vec3<double> tr = c.vec(j, "translate", p, Vec3<double>{0, 0, 0});
  if (is_zero(axis)) c.fail(p + ".rotate_axis", "zero axis");
  // Rodrigues' rotation matrix times the diagonal scale, then the translation column.
  const Vec3<double> a = normalize(axis);
  const double th = deg * std::numbers::pi / 180, co = std::cos(th), si = std::sin(th), ic = 1 - co;
  const double r[3][3] = {{co + a.x * a.x * ic, a.x * a.y * ic - a.z * si, a.x * a.z * ic + a.y * si},
                          {a.y * a.x * ic + a.z * si, co + a.y * a.y * ic, a.y * a.z * ic - a.x * si},
                          {a.z * a.x * ic - a.y * si, a.z * a.y * ic + a.x * si, co + a.z * a.z * ic}};
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) t.m[i][k] = r[i][k] * s[k];
    t.m[i][3] = tr[i];
  }
  return t;
}

Camera camera_of(const Ctx& c, const json& j) {
  const std::string p = "camera";
  c.keys(j, p, {"type", "eye", "target", "up", "fov_y_degrees", "width", "height", "half_width", "half_height"});
  const std::string type = c.str(j, "type", p, "perspective");
  const Vec3<double> eye = c.vec(j, "eye", p), target = c.vec(j, "target", p), up = c.vec(j, "up", p, Vec3<double>{0, 1, 0});
  if (eye == target) c.fail(p, "eye equals target");
  if (is_zero(cross(up, eye - target))) c.fail(p + ".up", "parallel to the view direction");
  const int w = c.dim(j, "width", p, 320), h = c.dim(j, "height", p, 240);
  if (type == "perspective") {
    const double fov = c.num(j, "fov_y_degrees", p, 45.0);
    if (!(fov > 0 && fov < 180)) c.fail(p + ".fov_y_degrees", "must be in (0, 180)");
    return {PerspectiveCamera<double>::look_at(w, h, fov * std::numbers::pi / 180, eye, target, up)};
  }
  if (type != "orthographic") c.fail(p + ".type", "expected \"perspective\" or \"orthographic\"");
  const double hw = c.num(j, "half_width", p, 1.0), hh = c.num(j, "half_height", p, 1.0);
  if (!(hw > 0 && hh > 0)) c.fail(p, "half_width and half_height must be positive");
  return {OrthographicCamera<double>{w, h, look_at(eye, target, up), -hw, hw, -hh, hh}};
}

template <class F>
void each(const Ctx& c, const json& root, const char* key, F&& f) {
  if (!root.contains(key)) return;
  const json& a = root[key];
  if (!a.is_array()) c.fail(key, "expected an array");
  for (std::size_t i = 0; i < a.size(); ++i) f(a[i], std::string(key) + "[" + std::to_string(i) + "]");
}

}  // namespace

Scene parse_scene_json(const std::string& text, const std::string& base_dir, const std::string& name) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    throw SceneError(name + ": byte " + std::to_string(e.byte) + ": invalid JSON (" + short_what(e) + ")");
  } catch (const json::out_of_range& e) {
    // A number beyond double's range ("1e999"): nlohmann names the token but not its offset, so
    // the message gives the first offset where that token occurs.
    const std::string what = short_what(e);
    const auto a = what.find('\''), b = what.rfind('\'');
    const std::size_t at = a < b ? text.find(what.substr(a + 1, b - a - 1)) : std::string::npos;
    throw SceneError(name + ": byte " + std::to_string(at == std::string::npos ? 0 : at + 1) + ": number out of range (" +
                     what + ")");
  }
  const Ctx c{name};
  c.keys(root, "(top level)", {"camera", "meshes", "spheres", "ellipsoids", "disks", "boxes", "lights"});
  Scene s;
  each(c, root, "meshes", [&](const json& j, const std::string& p) {
    c.keys(j, p, {"file", "scale", "rotate_axis", "rotate_degrees", "translate", "matrix"});
    if (!j.contains("file") || !j["file"].is_string()) c.fail(p, "missing 'file' (a string)");
    std::filesystem::path f = j["file"].get<std::string>();
    if (f.is_relative()) f = std::filesystem::path(base_dir) / f;
    try {
      add_mesh(s, mesh::read_mesh(f.string()), mesh_transform(c, j, p));
    } catch (const mesh::MeshError& e) {
      c.fail(p + ".file", e.what());
    }
  });
  each(c, root, "spheres", [&](const json& j, const std::string& p) {
    c.keys(j, p, {"center", "radius"});
    s.spheres.push_back({c.vec(j, "center", p), c.num(j, "radius", p)});
  });
  each(c, root, "ellipsoids", [&](const json& j, const std::string& p) {
    c.keys(j, p, {"center", "semi_axes"});
    s.ellipsoids.push_back({c.vec(j, "center", p), c.vec(j, "semi_axes", p)});
  });
  each(c, root, "disks", [&](const json& j, const std::string& p) {
    c.keys(j, p, {"center", "normal", "radius"});
    s.disks.push_back({c.vec(j, "center", p), c.vec(j, "normal", p), c.num(j, "radius", p)});
  });
  each(c, root, "boxes", [&](const json& j, const std::string& p) {
    c.keys(j, p, {"lo", "hi"});
    s.boxes.push_back({c.vec(j, "lo", p), c.vec(j, "hi", p)});
  });
  each(c, root, "lights", [&](const json& j, const std::string& p) {
    c.keys(j, p, {"type", "center", "normal", "radius", "emission"});
    if (c.str(j, "type", p, "disk") != "disk") c.fail(p + ".type", "only \"disk\" lights exist");
    s.lights.push_back({{c.vec(j, "center", p), c.vec(j, "normal", p), c.num(j, "radius", p)},
                        c.vec(j, "emission", p, Vec3<double>{1, 1, 1})});
  });
  if (root.contains("camera")) s.camera = camera_of(c, root["camera"]);
  return s;
}

Scene load_scene(const std::string& path) {
  if (mesh::is_mesh_path(path)) {
    Scene s;
    try {
      add_mesh(s, mesh::read_mesh(path));
    } catch (const mesh::MeshError& e) {
      throw SceneError(e.what());
    }
    // A mesh file with nothing to hit (empty, or vertices only) is more likely a mistake than a scene.
    if (s.mesh.triangles.empty()) throw SceneError(path + ": no triangles in the file");
    return s;
  }
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw SceneError(path + ": no such file");
  if (std::filesystem::is_directory(path, ec)) throw SceneError(path + ": is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_scene_json(ss.str(), std::filesystem::path(path).parent_path().string(), path);
}

}  // namespace rayproof::scene
