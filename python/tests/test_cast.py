"""rayproof.Mesh against `rayproof cast` on a small closed mesh, and no leaks with robust."""
import numpy as np
import pytest

import rayproof
from conftest import run_cli, same_float


def icosphere(subdivisions, rng):
    """A closed icosphere (vertices shared) with every vertex pushed off the unit sphere a little."""
    g = (1 + 5 ** 0.5) / 2
    v = [[-1, g, 0], [1, g, 0], [-1, -g, 0], [1, -g, 0], [0, -1, g], [0, 1, g],
         [0, -1, -g], [0, 1, -g], [g, 0, -1], [g, 0, 1], [-g, 0, -1], [-g, 0, 1]]
    f = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
         [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
         [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    v = [np.array(p, dtype=float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        mid, nf = {}, []
        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                p = v[a] + v[b]
                v.append(p / np.linalg.norm(p))
                mid[k] = len(v) - 1
            return mid[k]
        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
        f = nf
    v = np.array(v) * (1 + 0.05 * rng.uniform(-1, 1, (len(v), 1)))
    return v, np.array(f, dtype=np.uint32)


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    rng = np.random.default_rng(12)
    v, f = icosphere(2, rng)  # 320 triangles
    d = tmp_path_factory.mktemp("cast")
    off = d / "mesh.off"
    off.write_text(f"OFF\n{len(v)} {len(f)} 0\n" + "".join(f"{x!r} {y!r} {z!r}\n" for x, y, z in v.tolist())
                   + "".join(f"3 {a} {b} {c}\n" for a, b, c in f.tolist()))
    # Rays from inside and outside in random directions, through vertices, and invalid ones.
    o = np.vstack([rng.uniform(-0.5, 0.5, (60, 3)), rng.uniform(-3, 3, (60, 3)), np.zeros((len(v), 3)),
                   [[np.nan, 0, 0], [0, 0, 0]]])
    dirs = np.vstack([rng.normal(size=(60, 3)), -o[60:120] + rng.normal(scale=0.3, size=(60, 3)), v,
                      [[1, 0, 0], [0, 0, 0]]])
    rays = d / "rays.txt"
    rays.write_text("".join(" ".join(repr(x) for x in row) + "\n" for row in np.hstack([o, dirs]).tolist()))
    return v, f, off, rays, o, dirs


def cli_hits(line):
    """`CLASS T PRIM ...` triples of a cast output line; [] for `miss - -` or `invalid - -`."""
    tok = line.split()
    if tok[1] == "-":
        return []
    return [(tok[i], float(tok[i + 1]), int(tok[i + 2])) for i in range(0, len(tok), 3)]


@pytest.mark.parametrize("method", ["float", "robust", "certified"])
def test_closest_equals_the_command_line_tool(scene, method):
    v, f, off, rays, o, d = scene
    mesh = rayproof.Mesh(v, f)
    assert (mesh.num_vertices, mesh.num_triangles) == (len(v), len(f))
    r = mesh.closest(o, d, method=method)
    lines = run_cli("cast", off, rays, "--method", method, "--query", "closest")
    assert len(lines) == len(o)
    for i, line in enumerate(lines):
        want = cli_hits(line)
        if not want:
            assert r["classes"][i] == line.split()[0] and r["prim"][i] == -1 and not r["hit"][i]
            assert np.isnan(r["t"][i])
        else:
            (c, t, p), = want
            assert (r["classes"][i], r["prim"][i]) == (c, p) and r["hit"][i]
            assert same_float(r["t"][i], t)
    assert r["classes"][-2] == "invalid" and r["classes"][-1] == "invalid"
    assert r["hit"][:60].all()  # from inside a closed mesh every ray hits


@pytest.mark.parametrize("method", ["float", "robust", "certified"])
def test_any_and_all_equal_the_command_line_tool(scene, method):
    v, f, off, rays, o, d = scene
    mesh = rayproof.Mesh(v.astype(np.float64), f.astype(np.int64))
    anyhit = mesh.any(o, d, method=method)
    assert anyhit.dtype == bool
    assert list(anyhit) == [s == "hit" for s in run_cli("cast", off, rays, "--method", method, "--query", "any")]
    a = mesh.all(o, d, method=method)
    lines = run_cli("cast", off, rays, "--method", method, "--query", "all")
    for i, line in enumerate(lines):
        want = cli_hits(line)
        b, e = a["offsets"][i], a["offsets"][i + 1]
        assert (a["ray"][b:e] == i).all()
        assert list(a["classes"][b:e]) == [w[0] for w in want]
        assert list(a["prim"][b:e]) == [w[2] for w in want]
        assert same_float(a["t"][b:e], [w[1] for w in want]).all()
    # A ray from inside a closed mesh crosses it an odd number of times.
    counts = np.diff(a["offsets"])[:60]
    if method != "float":
        assert (counts % 2 == 1).all()


def test_no_leaks_with_robust_through_vertices_and_edges(scene):
    v, f, *_ = scene
    mesh = rayproof.Mesh(v.astype(np.float32), f)  # float32 vertices are accepted (and exact in double)
    vf = v.astype(np.float32).astype(np.float64)
    edges = np.vstack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    targets = np.vstack([vf, (vf[edges[:, 0]] + vf[edges[:, 1]]) / 2])
    origins = np.array([[0, 0, 0], [0.1, -0.2, 0.05], [-0.3, 0.2, 0.1]])
    for origin in origins:
        for method in ("robust", "certified"):
            r = mesh.closest(origin, targets - origin, method=method, threads=1)
            assert r["hit"].all(), f"{method} leaked {np.count_nonzero(~r['hit'])} of {len(targets)} rays"
            assert mesh.any(origin, targets - origin, method=method).all()


def test_tmin_tmax(scene):
    v, f, *_ = scene
    mesh = rayproof.Mesh(v, f)
    o, d = [-5, 0, 0], [1, 0.1234, 0.0567]  # through two triangle interiors
    a = mesh.all(o, d, method="certified")
    assert list(a["classes"]) == ["interior", "interior"]
    t_in, t_out = a["t"]
    assert mesh.closest(o, d, method="certified")["t"][0] == t_in
    assert mesh.closest(o, d, method="certified", tmin=(t_in + t_out) / 2)["t"][0] == t_out
    assert not mesh.closest(o, d, method="certified", tmax=t_in * 0.99)["hit"][0]
    assert not mesh.any(o, d, method="robust", tmin=t_out * 1.01)[0]
    assert list(mesh.all(o, d, method="certified", tmin=(t_in + t_out) / 2)["t"]) == [t_out]


def test_barycentrics_locate_the_hit(scene):
    v, f, off, rays, o, d = scene
    mesh = rayproof.Mesh(v, f)
    for method in ("float", "robust"):
        r = mesh.closest(o[:120], d[:120], method=method)
        h = r["hit"]
        tri = v[f[r["prim"][h]]]
        b1, b2 = r["b1"][h], r["b2"][h]
        assert ((b1 >= 0) & (b2 >= 0) & (b1 + b2 <= 1)).all()
        p = (1 - b1 - b2)[:, None] * tri[:, 0] + b1[:, None] * tri[:, 1] + b2[:, None] * tri[:, 2]
        assert np.allclose(p, o[:120][h] + r["t"][h][:, None] * d[:120][h], atol=1e-5)
    assert np.isnan(mesh.closest(o[:5], d[:5], method="certified")["b1"]).all()
