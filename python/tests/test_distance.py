"""Mesh.distance / signed_distance / closest_points: distances on a cube known in closed form
(box distance outside, distance to the nearest face inside), ties by symmetry (the lowest triangle),
points on vertices, invalid points, shapes, the GIL released, and agreement with the command-line tool."""
import threading

import numpy as np

import rayproof
from conftest import run_cli

CUBE_V = np.array([[2 * (i & 1), 2 * (i >> 1 & 1), 2 * (i >> 2 & 1)] for i in range(8)], dtype=np.float64)
CUBE_T = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                   [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]], dtype=np.uint32)


def cube_distance(p):
    """[0, 2]^3: outside the Euclidean distance to the box, inside the distance to the nearest face."""
    outside = np.linalg.norm(np.maximum(np.maximum(-p, p - 2), 0), axis=1)
    inside = np.min(np.concatenate([p, 2 - p], axis=1), axis=1)
    return np.where(np.all((p > 0) & (p < 2), axis=1), inside, outside)


def test_cube_distances_and_signs():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    g = np.arange(-1.0, 3.01, 0.25)  # dyadic: the closed form is exact or correctly rounded by numpy
    p = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
    d = m.distance(p)
    assert d.dtype == np.float64 and d.shape == (len(p),)
    np.testing.assert_array_equal(d, cube_distance(p))
    s = m.signed_distance(p)
    side = m.contains(p)
    np.testing.assert_array_equal(s, np.where(side == rayproof.INSIDE, -d, np.where(side == rayproof.SURFACE, 0.0, d)))
    assert (s < 0).sum() > 100 and (s == 0).sum() > 100


def test_closest_points_ties_vertices_and_invalid():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    p = np.array([[1, 1, 1], [3, 3, 3], [0, 0, 0], [1, 1, -0.5], [np.nan, 0, 0]])
    r = m.closest_points(p, side=True)
    np.testing.assert_array_equal(r["triangles"], [0, 3, 0, 0, -1])  # the lowest among exact ties
    np.testing.assert_array_equal(r["distance"][:4], [1.0, np.sqrt(3.0), 0.0, 0.5])
    assert np.isnan(r["distance"][4])
    np.testing.assert_array_equal(r["points"][1], [2, 2, 2])
    np.testing.assert_array_equal(r["points"][3], [1, 1, 0])
    np.testing.assert_allclose(r["barycentric"][:4].sum(axis=1), 1.0)
    np.testing.assert_array_equal(r["side"], [rayproof.INSIDE, rayproof.OUTSIDE, rayproof.SURFACE, rayproof.OUTSIDE,
                                              rayproof.INVALID])
    assert m.distance([3.0, 1.0, 1.0]).shape == (1,)
    assert "side" not in m.closest_points(p[:2])


def test_gil_released_and_batch_matches_one_by_one():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    rng = np.random.default_rng(4)
    p = rng.uniform(-1, 3, size=(200000, 3))
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)

    t = threading.Thread(target=count)
    t.start()
    d = m.distance(p, threads=1)
    stop.set()
    t.join()
    assert len(ticks) > 10  # the other thread ran during the call
    np.testing.assert_array_equal(d[:50], [m.distance(q)[0] for q in p[:50]])
    np.testing.assert_allclose(d, cube_distance(p), rtol=1e-15)


def test_agrees_with_the_command_line(tmp_path):
    off = tmp_path / "cube.off"
    off.write_text("OFF\n8 12 0\n" + "".join(f"{x} {y} {z}\n" for x, y, z in CUBE_V) +
                   "".join(f"3 {a} {b} {c}\n" for a, b, c in CUBE_T))
    p = np.random.default_rng(1).uniform(-1, 3, size=(100, 3))
    pts = tmp_path / "p.txt"
    pts.write_text("".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in p))
    lines = run_cli("distance", off, pts)
    r = rayproof.Mesh(CUBE_V, CUBE_T).closest_points(p, side=True)
    np.testing.assert_array_equal([float(x.split()[0]) for x in lines], r["distance"])
    assert [x.split()[1] for x in lines] == [["outside", "inside", "surface"][k] for k in r["side"]]
    np.testing.assert_array_equal([int(x.split()[2]) for x in lines], r["triangles"])
