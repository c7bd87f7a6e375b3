"""rayproof.check_crossings: all-hits functions (a Python function over arrays of rays) judged on a
mesh. rayproof's own crossings (Mesh.crossings' dict, or the (t, triangle, offsets) tuple) get no
finding; a numpy Möller–Trumbore loop is caught with duplicates or missing crossings at shared edges;
a dropped hit, a duplicated one, hits on an invalid ray and a raising function get exactly the
expected counts; bad results and options are refused."""
import numpy as np
import pytest

import rayproof

TINY = 5e-324  # crossings at t > 0


def cube():
    v = np.array([[i & 1, (i >> 1) & 1, (i >> 2) & 1] for i in range(8)], dtype=np.float64)
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    f = [t for q in quads for t in ([q[0], q[1], q[2]], [q[0], q[2], q[3]])]
    return v, np.array(f, dtype=np.int64)


def own(v, f):
    mesh = rayproof.Mesh(v, f)
    return lambda o, d: mesh.crossings(o, d, tmin=TINY)


def test_rayproofs_own_crossings_have_no_finding():
    v, f = cube()
    res = rayproof.check_crossings(own(v, f), v, f, random_rays=200)
    assert res["findings"] == 0, res["reproducers"]
    assert res["crossings"] > 500 and res["hits"] == res["crossings"]
    assert res["max_ulps"] <= 1  # its t: within one ulp of the exact t
    assert set(res["sets"]) == {"leak", "graze", "face", "surface", "random", "extreme", "invalid"}
    assert res["cost_ratio"] is not None and res["cost_ratio"] > 0

    def as_tuple(o, d):
        r = own(v, f)(o, d)
        return r["t"], r["prim"], r["offsets"]
    assert rayproof.check_crossings(as_tuple, v, f, random_rays=200, precision="float")["findings"] == 0


def test_numpy_moller_trumbore_is_caught():
    v, f = cube()
    p0, e1, e2 = v[f[:, 0]], v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]

    def mt(o, d):
        ts, ks, off = [], [], [0]
        with np.errstate(all="ignore"):
            for oi, di in zip(o, d):
                p = np.cross(di[None, :], e2)
                det = np.einsum("tk,tk->t", e1, p)
                s = oi[None, :] - p0
                q = np.cross(s, e1)
                u, w, t = np.einsum("tk,tk->t", s, p) / det, (q @ di) / det, np.einsum("tk,tk->t", e2, q) / det
                hit = np.nonzero((det != 0) & (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 0))[0]
                hit = hit[np.argsort(t[hit], kind="stable")]
                ts += list(t[hit]); ks += list(hit); off.append(len(ts))
        return np.array(ts, dtype=np.float64), np.array(ks, dtype=np.int64), np.array(off)

    res = rayproof.check_crossings(mt, v, f, random_rays=100)
    assert res["duplicates"] + res["missing"] > 0
    assert res["findings"] > 0 and res["reproducers"]


def test_wrong_answers_move_their_counts():
    v, f = cube()
    mesh = rayproof.Mesh(v, f)
    o = np.array([[0.25, 0.5, -1.0], [0.25, 0.5, -1.0], [np.nan, 0, 0], [0.25, 0.5, -1.0]])
    d = np.array([[0, 0, 1.0], [0, 0, 1.0], [0, 0, 1.0], [0, 0, 1.0]])

    def wrong(oo, dd):
        r = mesh.crossings(oo, dd, tmin=TINY)
        t, k, off = list(r["t"]), list(r["prim"]), r["offsets"]
        rows = [list(zip(t[off[i]:off[i + 1]], k[off[i]:off[i + 1]])) for i in range(len(oo))]
        rows[0] = rows[0][1:]                  # ray 0: the entry dropped
        rows[1] = [rows[1][0]] + rows[1]       # ray 1: the entry twice
        rows[2] = [(1.0, 0)]                   # ray 2 (NaN origin): a hit
        flat = [h for row in rows for h in row]
        offsets = np.cumsum([0] + [len(row) for row in rows])
        return np.array([h[0] for h in flat]), np.array([h[1] for h in flat]), offsets

    res = rayproof.check_crossings(wrong, v, f, rays=(o, d))
    assert (res["rays"], res["crossings"], res["invalid_rays"]) == (4, 6, 1)
    assert (res["missing"], res["duplicates"], res["invalid_hit"]) == (1, 1, 1)
    assert res["findings"] == 3
    assert list(res["sets"]) == ["user"]

    def raises(oo, dd):
        raise RuntimeError("no hits today")
    r = rayproof.check_crossings(raises, v, f, rays=(o, d))
    assert (r["failures"], r["invalid_failures"]) == (3, 1)
    assert any("no hits today" in n for n in r["notes"])

    def bad_offsets(oo, dd):
        return np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros(2)
    assert rayproof.check_crossings(bad_offsets, v, f, rays=(o, d))["failures"] == 3
    with pytest.raises(ValueError):
        rayproof.check_crossings(raises, v, f, precision="half")
    with pytest.raises(ValueError):
        rayproof.check_crossings(raises, v, f, sets=["nope"])
