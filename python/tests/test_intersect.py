"""Mesh.self_intersections / intersecting_pairs: a closed cube has none, two cubes touching at a face
under other indices intersect, a shared edge counts only when the triangles overlap, a zero-area
triangle is the row (i, i); the pairs equal the command-line tool's; shapes and dtypes."""
import numpy as np

import rayproof
from conftest import run_cli

CUBE_T = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                   [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]], dtype=np.uint32)


def cube(lo, size=2.0):
    return np.array([[lo[0] + size * (i & 1), lo[1] + size * (i >> 1 & 1), lo[2] + size * (i >> 2 & 1)]
                     for i in range(8)], dtype=np.float64)


def two(v1, v2):
    return np.concatenate([v1, v2]), np.concatenate([CUBE_T, CUBE_T + 8])


def test_closed_cube_has_none():
    p = rayproof.Mesh(cube((0, 0, 0)), CUBE_T).self_intersections()
    assert p.shape == (0, 2) and p.dtype == np.int64


def test_touching_cubes_with_other_indices_intersect():
    v, t = two(cube((0, 0, 0)), cube((2, 0, 0)))
    p = rayproof.Mesh(v, t).self_intersections(threads=1)
    assert p.shape[1] == 2 and len(p) > 4
    rows = {tuple(r) for r in p}
    assert {(10, 20), (10, 21), (11, 20), (11, 21)} <= rows
    assert all(i < 12 <= j for i, j in rows)  # each cube alone is clean
    np.testing.assert_array_equal(p, np.array(sorted(rows)))
    # The same pairs between the two cubes as two meshes, with the second's triangles renumbered.
    q = rayproof.Mesh(cube((0, 0, 0)), CUBE_T).intersecting_pairs(rayproof.Mesh(cube((2, 0, 0)), CUBE_T))
    np.testing.assert_array_equal(q, p - [0, 12])


def test_shared_edge_and_zero_area():
    v = np.array([[0, 0, 0], [4, 0, 0], [2, 2, 0], [2, 1, 0], [2, -2, 0], [2, 1, 1], [1, 0, 0]], dtype=np.float64)
    t = np.array([[0, 1, 2], [1, 0, 3], [1, 0, 4], [1, 0, 5], [0, 6, 1]])
    np.testing.assert_array_equal(rayproof.Mesh(v, t).self_intersections(), [[0, 1], [4, 4]])


def test_equals_the_cli(tmp_path):
    v, t = two(cube((0, 0, 0)), cube((1, 1, 1)))
    path = tmp_path / "cubes.off"
    path.write_text("OFF\n{} {} 0\n".format(len(v), len(t)) + "".join("{} {} {}\n".format(*x) for x in v)
                    + "".join("3 {} {} {}\n".format(*x) for x in t))
    p = rayproof.Mesh(v, t).self_intersections()
    assert len(p) > 0
    assert run_cli("intersect", path) == ["{} {}".format(i, j) for i, j in p]
    assert run_cli("intersect", path, "--count") == [str(len(p))]


def test_empty_mesh_and_bad_vertices():
    m = rayproof.Mesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
    assert m.self_intersections().shape == (0, 2) and m.intersecting_pairs(m).shape == (0, 2)
    try:
        rayproof.Mesh(np.array([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]]), np.array([[0, 1, 2]]))
    except ValueError as e:
        assert "NaN or infinite" in str(e)
    else:
        raise AssertionError("a NaN vertex was accepted")
