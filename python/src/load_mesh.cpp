/// rayproof.load_mesh(path): a mesh file as numpy arrays, read by the command-line tool's own
/// readers (src/mesh: OFF, OBJ, PLY, STL by rayproof, glTF 2.0 through tinygltf).
#include <pybind11/pybind11.h>
#include <pybind11/stl/filesystem.h>

#include <fmt/core.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "bindings.h"
#include "mesh/mesh.h"

namespace rayproof::python {

void bind_load_mesh(py::module_& m) {
  using namespace pybind11::literals;
  // MeshError: a ValueError whose message names the file and the place ("FILE:LINE: ...", "FILE:
  // byte N: ...", "FILE: accessors[2]: ...").
  py::register_exception<mesh::MeshError>(m, "MeshError", PyExc_ValueError);
  m.attr("MeshError").attr("__doc__") =
      "A mesh file that cannot be read: the message names the file and the line, byte or glTF object.";
  m.def(
      "load_mesh",
      [](const std::filesystem::path& path) {
        const std::string name = path.string();
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
          // FileNotFoundError, as open() raises it.
          PyErr_SetObject(PyExc_FileNotFoundError,
                          py::make_tuple(ENOENT, fmt::format("{}: no such file", name), name).ptr());
          throw py::error_already_set();
        }
        mesh::Mesh mesh;
        {
          py::gil_scoped_release unlocked;
          mesh = mesh::read_mesh(name);  // MeshError -> rayproof.MeshError
        }
        py::array_t<double> v({static_cast<py::ssize_t>(mesh.vertices.size()), py::ssize_t{3}});
        py::array_t<std::uint32_t> t({static_cast<py::ssize_t>(mesh.triangles.size()), py::ssize_t{3}});
        double* vp = v.mutable_data();
        for (const auto& p : mesh.vertices) *vp++ = p.x, *vp++ = p.y, *vp++ = p.z;
        if (!mesh.triangles.empty()) std::memcpy(t.mutable_data(), mesh.triangles.data(), mesh.triangles.size() * 12);
        return py::make_tuple(v, t);
      },
      "path"_a,
      R"doc(Reads a mesh file with the command-line tool's readers: OFF, OBJ, PLY, STL (rayproof's own readers) and glTF 2.0
.gltf/.glb (tinygltf), chosen by the extension. Returns (vertices, indices): float64 (n, 3) and uint32 (m, 3), ready for
rayproof.Mesh(vertices, indices); polygons are fan-triangulated, glTF nodes' transforms applied. A file that cannot be read
raises rayproof.MeshError (a ValueError) naming the file and the line, byte or glTF object; a missing file raises
FileNotFoundError. rayproof.mesh_reader(path) says which reader answers a path.)doc");
  m.def(
      "mesh_reader",
      [](const std::filesystem::path& path) { return mesh::reader_name(mesh::format_of(path.string())); },
      "path"_a,
      "Which reader load_mesh uses for this path (by its extension): \"rayproof's OFF reader\", ..., \"tinygltf 2.7.0\"; "
      "rayproof.MeshError for an extension no reader takes.");
}

}  // namespace rayproof::python
