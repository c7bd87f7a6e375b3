"""Mesh.crossings: each crossing of a ray once with its direction, touches apart. A cube through faces, an
edge, a corner, grazing a silhouette and along a face; an open box; random rays on a closed mesh whose sum of
directions must equal minus the exact winding number at the origin; the command-line tool's answers; errors."""
import numpy as np
import pytest

import rayproof
from conftest import run_cli

CUBE_V = np.array([[2 * (i & 1), 2 * (i >> 1 & 1), 2 * (i >> 2 & 1)] for i in range(8)], dtype=np.float64)
CUBE_T = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                   [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]], dtype=np.uint32)

RAYS = np.array([
    [-1, 0.5, 0.75, 1, 0, 0],  # through two faces
    [-1, -1, 0.5, 1, 1, 0],    # through two vertical edges
    [-1, -1, -1, 1, 1, 1],     # through two corners
    [-1, 1, 1, 1, 0, 1],       # grazing the edge x = 0, z = 2
    [-1, 1, 2, 1, 0, 0],       # along the top face
    [1, 1, 1, 1, 0.25, 0.5],   # from inside
    [1, 1, 1, 0, 0, 0],        # zero direction
])


def per_ray(r, key, i, prefix=""):
    off = r[prefix + "offsets"]
    return r[key][off[i]:off[i + 1]]


def test_cube_each_crossing_once():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    r = m.crossings(RAYS[:, :3], RAYS[:, 3:], touches=True)
    assert r["direction"].dtype == np.int8 and len(r["offsets"]) == len(RAYS) + 1
    dirs = [list(per_ray(r, "direction", i)) for i in range(len(RAYS))]
    ts = [list(per_ray(r, "t", i)) for i in range(len(RAYS))]
    assert dirs[:3] == [[1, -1]] * 3 and ts[:3] == [[1.0, 3.0]] * 3
    assert dirs[3] == [] and list(per_ray(r, "touch_classes", 3, "touch_")) == ["edge"]
    assert dirs[4] == []
    assert sorted(per_ray(r, "touch_classes", 4, "touch_")) == ["coplanar", "coplanar", "edge", "edge"]
    assert dirs[5] == [-1] and ts[5] == [1.0]
    assert list(r["valid"]) == [True] * 6 + [False]
    # The crossed triangle is one of the face's two.
    assert set(per_ray(r, "prim", 0)) <= {8, 9, 10, 11}
    # Without touches: no touch arrays.
    assert "touch_t" not in m.crossings(RAYS[:, :3], RAYS[:, 3:])


def test_ranges_and_open_box():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    r = m.crossings([-1, 1, 1], [1, 0, 0], tmin=2, tmax=4)
    assert list(r["t"]) == [3.0] and list(r["direction"]) == [-1]
    opened = rayproof.Mesh(CUBE_V, np.delete(CUBE_T, [2, 3], axis=0))
    assert not opened.closed
    r = opened.crossings([[0.5, 0.75, 3], [0.5, 0.75, -1]], [[0, 0, -1], [0, 0, 1]])
    assert list(r["direction"]) == [-1, 1] and list(r["t"]) == [3.0, 1.0]


def bumpy_sphere(n=24, seed=3):
    """A closed oriented UV sphere with its vertices moved radially at random (self-intersections allowed)."""
    rng = np.random.default_rng(seed)
    th = np.linspace(0, np.pi, n + 1)[1:-1]
    ph = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
    v = [[0, 0, 1], [0, 0, -1]]
    for a in th:
        for b in ph:
            v.append([np.sin(a) * np.cos(b), np.sin(a) * np.sin(b), np.cos(a)])
    v = np.array(v) * rng.uniform(0.7, 1.3, size=(len(v), 1))
    ring = lambda i, j: 2 + i * 2 * n + j % (2 * n)
    t = []
    for j in range(2 * n):
        t.append([0, ring(0, j), ring(0, j + 1)])
        t.append([1, ring(n - 2, j + 1), ring(n - 2, j)])
    for i in range(n - 2):
        for j in range(2 * n):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j)
            t.append([a, d, c])
            t.append([a, c, b])
    return v, np.array(t)


def test_random_rays_net_equals_winding_change():
    v, t = bumpy_sphere()
    m = rayproof.Mesh(v, t)
    assert m.oriented
    rng = np.random.default_rng(1)
    o = rng.uniform(-1.5, 1.5, size=(3000, 3))
    # Half the rays aimed at vertices: the hard cases.
    d = rng.normal(size=(3000, 3))
    d[::2] = v[rng.integers(0, len(v), 1500)] - o[::2]
    r = m.crossings(o, d)
    net = np.add.reduceat(np.append(r["direction"].astype(np.int64), 0), r["offsets"][:-1])
    net[r["offsets"][:-1] == r["offsets"][1:]] = 0
    w = m.winding(o)
    ok = w != np.iinfo(np.int32).min
    np.testing.assert_array_equal(net[ok], -w[ok])
    # Each ray's crossings in t order.
    for i in range(0, 3000, 7):
        ts = per_ray(r, "t", i)
        assert np.all(np.diff(ts) >= 0)


def test_matches_the_command_line(tmp_path):
    mesh = tmp_path / "cube.off"
    mesh.write_text("OFF\n8 12 0\n" + "".join(f"{x:g} {y:g} {z:g}\n" for x, y, z in CUBE_V) +
                    "".join(f"3 {a} {b} {c}\n" for a, b, c in CUBE_T))
    rays = tmp_path / "rays.txt"
    rays.write_text("".join(" ".join(f"{x:g}" for x in row) + "\n" for row in RAYS))
    lines = run_cli("cast", mesh, rays, "--query", "crossings")
    r = rayproof.Mesh(CUBE_V, CUBE_T).crossings(RAYS[:, :3], RAYS[:, 3:])
    for i, line in enumerate(lines):
        if not r["valid"][i]:
            assert line == "invalid"
            continue
        fields = line.split()
        assert int(fields[0]) == r["offsets"][i + 1] - r["offsets"][i]
        for f, t, dr in zip(fields[1:], per_ray(r, "t", i), per_ray(r, "direction", i)):
            tt, name = f.split(":")
            assert float(tt) == t and name == ("in" if dr > 0 else "out")


def test_errors():
    m = rayproof.Mesh(CUBE_V, CUBE_T)
    with pytest.raises(ValueError):
        m.crossings([0, 0, 0], [1, 0, 0], tmin=2, tmax=1)
    with pytest.raises(ValueError):
        m.crossings(np.zeros((3, 2)), np.zeros((3, 3)))
    r = m.crossings([np.nan, 0, 0], [1, 0, 0])
    assert list(r["valid"]) == [False] and len(r["t"]) == 0
