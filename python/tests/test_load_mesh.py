"""rayproof.load_mesh: mesh files through the command-line tool's readers, errors that name the file
and the place, and the same answers as `rayproof cast` on the same file."""
import numpy as np
import pytest

import rayproof
from conftest import run_cli

TET_OFF = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"


def test_off_obj_and_stl_give_the_same_mesh(tmp_path):
    off = tmp_path / "tet.off"
    off.write_text(TET_OFF)
    v, i = rayproof.load_mesh(off)
    assert v.dtype == np.float64 and v.shape == (4, 3)
    assert i.dtype == np.uint32 and i.shape == (4, 3)
    assert v.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    assert i.tolist() == [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    obj = tmp_path / "tet.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    v2, i2 = rayproof.load_mesh(str(obj))
    assert (v2 == v).all() and (i2 == i).all()
    assert rayproof.mesh_reader(off) == "rayproof's OFF reader"
    assert rayproof.mesh_reader("x.glb").startswith(("tinygltf ", "none"))


def test_quads_are_fan_triangulated_and_cast_as_the_cli_casts(tmp_path):
    off = tmp_path / "quad.off"
    off.write_text("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
    v, i = rayproof.load_mesh(off)
    assert i.tolist() == [[0, 1, 2], [0, 2, 3]]
    rays = tmp_path / "rays.txt"
    rays.write_text("0.25 0.75 1 0 0 -1\n0.75 0.25 1 0 0 -1\n2 2 1 0 0 -1\n")
    cli = run_cli("cast", "--method", "robust", off, rays)
    hits = rayproof.Mesh(v, i).closest(np.array([[0.25, 0.75, 1], [0.75, 0.25, 1], [2, 2, 1]]),
                                       np.array([[0, 0, -1.0]] * 3), method="robust")
    for line, hit, prim in zip(cli, hits["hit"], hits["prim"]):
        words = line.split()
        assert (words[0] != "miss") == bool(hit)
        if hit:
            assert int(words[2]) == prim


def test_errors_name_the_file_and_the_line(tmp_path):
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n")
    with pytest.raises(rayproof.MeshError, match=r"bad\.off:4: ") as e:
        rayproof.load_mesh(bad)
    assert isinstance(e.value, ValueError)
    (tmp_path / "m.xyz").write_text("")
    with pytest.raises(rayproof.MeshError, match=r"unknown mesh format '\.xyz'"):
        rayproof.load_mesh(tmp_path / "m.xyz")
    with pytest.raises(FileNotFoundError, match="no such file"):
        rayproof.load_mesh(tmp_path / "absent.off")
    stl = tmp_path / "short.stl"
    stl.write_bytes(b"\0" * 80 + b"\5\0\0\0" + b"\0" * 10)
    with pytest.raises(rayproof.MeshError, match=r"short\.stl: byte \d+: "):
        rayproof.load_mesh(stl)


def test_gltf_when_built_with_tinygltf(tmp_path):
    if not rayproof.mesh_reader("x.gltf").startswith("tinygltf"):
        pytest.skip("built without tinygltf (Debian: libtinygltf-dev)")
    import base64
    buf = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32).tobytes() + \
        np.array([0, 1, 2], dtype=np.uint16).tobytes() + b"\0\0"
    uri = "data:application/octet-stream;base64," + base64.b64encode(buf).decode()
    gltf = tmp_path / "tri.gltf"
    gltf.write_text('{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 0},'
                    ' "indices": 1}]}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3,'
                    ' "type": "VEC3"}, {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],'
                    ' "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36,'
                    ' "byteLength": 6}], "buffers": [{"byteLength": 44, "uri": "' + uri + '"}]}')
    v, i = rayproof.load_mesh(gltf)
    assert v.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]] and i.tolist() == [[0, 1, 2]]
    gltf.write_text(gltf.read_text().replace('"indices": 1}', '"indices": 1, "mode": 0}'))
    with pytest.raises(rayproof.MeshError, match=r"tri\.gltf: meshes\[0\]\.primitives\[0\]: mode 0 \(points\)"):
        rayproof.load_mesh(gltf)
