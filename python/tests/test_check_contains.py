"""rayproof.check_contains: containment functions (a Python function over an array of points) judged
on a mesh. rayproof's own Mesh.contains gets no finding; a naive numpy parity test is caught on the
surface sets; inverted, raising and garbage-returning functions get exactly the expected counts."""
import numpy as np
import pytest

import rayproof


def cube(dx=0.0, top=True):
    v = np.array([[i & 1, (i >> 1) & 1, (i >> 2) & 1] for i in range(8)], dtype=np.float64) + [dx, 0, 0]
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    f = []
    for k, q in enumerate(quads):
        if top or k != 1:
            f += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    return v, np.array(f, dtype=np.int64)


def two_cubes():
    v0, f0 = cube()
    v1, f1 = cube(0.5)
    return np.vstack([v0, v1]), np.vstack([f0, f1 + 8])


def exact(v, f, rule="automatic"):
    mesh = rayproof.Mesh(v, f)

    def fn(p):
        s = mesh.contains(p, rule=rule).astype(np.int64)
        return np.where(s == 3, 0, s)  # invalid points: outside

    return fn


def naive_parity(v, f):
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]

    def orient(a, b, py, pz):
        return (b[..., 1] - a[..., 1]) * (pz - a[..., 2]) - (b[..., 2] - a[..., 2]) * (py - a[..., 1])

    d = orient(a, b, c[:, 1], c[:, 2])

    def fn(p):
        with np.errstate(all="ignore"):
            py, pz = p[:, 1:2], p[:, 2:3]
            u, w = orient(b, c, py, pz) / d, orient(c, a, py, pz) / d
            x = u * a[:, 0] + w * b[:, 0] + (1 - u - w) * c[:, 0]
            hit = (d != 0) & (u >= 0) & (w >= 0) & (1 - u - w >= 0) & (x > p[:, 0:1])
        return hit.sum(axis=1) & 1

    return fn


def test_rayproofs_own_contains_has_no_finding():
    for v, f in (cube(), cube(top=False), two_cubes()):
        res = rayproof.check_contains(exact(v, f), v, f, random_points=200, max_points_per_set=200)
        assert res["findings"] == 0, res["reproducers"]
        assert res["surface"] > 0 and res["surface_said_surface"] == res["surface"]
        assert res["points"] == sum(s["points"] for s in res["sets"].values())
        assert res["invalid_points"] == 10
        assert res["contains_seconds"] > 0 and res["cost_ratio"] is not None
    assert rayproof.check_contains(exact(*cube(top=False)), *cube(top=False), random_points=10)["rule"] == "winding"


def test_naive_parity_is_caught_with_exact_reproducers():
    v, f = cube()
    res = rayproof.check_contains(naive_parity(v, f), v, f, random_points=200, mesh_name="cube")
    assert res["findings"] > 0
    assert res["sets"]["random"]["findings"] == 0  # away from edges and vertices it is right
    assert res["sets"]["nudged"]["findings"] > 0
    line = res["reproducers"][0]
    assert " mesh=cube point " in line and " exact: " in line and " answer: " in line
    # The point in the reproducer reads back to the point judged: the same answer again.
    coords = line.split(" point ")[1].split(" exact: ")[0].split()
    p = np.array([[float(x) for x in coords]])
    again = rayproof.check_contains(naive_parity(v, f), v, f, points=p)
    assert again["findings"] == 1


def test_inverted_raising_and_garbage_get_exactly_the_expected_counts():
    v, f = cube()
    mesh = rayproof.Mesh(v, f)
    p = np.array([[0.5, 0.5, 0.5], [2.0, 0.5, 0.5], [0.25, 0.25, 0.25], [1.0, 0.5, 0.5], [np.nan, 0, 0]])

    def inverted(q):
        s = mesh.contains(q).astype(np.int64)
        return np.where(s == 0, 1, np.where(s == 1, 0, s))

    res = rayproof.check_contains(inverted, v, f, points=p)
    assert (res["inside_called_outside"], res["outside_called_inside"], res["surface_said_surface"]) == (2, 1, 1)
    assert res["invalid_points"] == 1 and res["garbage"] == 1  # 3 is no answer, even on a NaN point
    assert res["findings"] == 4

    res = rayproof.check_contains(lambda q: np.full(len(q), 0.5), v, f, points=p)
    assert res["garbage"] == 5
    assert all("answer: not-an-integer" in r for r in res["reproducers"])
    res = rayproof.check_contains(lambda q: np.full(len(q), 2), v, f, points=p)
    assert res["false_surface"] == 3 and res["invalid_said_surface"] == 1 and res["findings"] == 3

    def boom(q):
        raise RuntimeError("no tree today")

    res = rayproof.check_contains(boom, v, f, random_points=50, batch=7)
    assert res["failures"] + res["invalid_failures"] == res["points"]
    assert res["invalid_failures"] == res["invalid_points"] == 10
    assert any("no tree today" in n for n in res["notes"])
    res = rayproof.check_contains(lambda q: np.zeros(len(q) + 1), v, f, points=p)
    assert res["failures"] == 4 and any("shape" in n for n in res["notes"])


def test_rules_on_overlapping_shells():
    v, f = two_cubes()
    parity = exact(v, f, rule="parity")
    auto = rayproof.check_contains(parity, v, f, random_points=300)
    assert auto["findings"] == 0 and auto["rules_differ"] > 0
    assert auto["rules_differ_other"] == auto["rules_differ"]
    named = rayproof.check_contains(parity, v, f, rule="nonzero", random_points=300)
    assert named["findings"] == named["inside_called_outside"] == named["rules_differ"]
    assert rayproof.check_contains(parity, v, f, rule="parity", random_points=300)["findings"] == 0


def test_float_precision_gives_float_points():
    v, f = cube()
    seen = []

    def fn(p):
        seen.append(p.copy())
        return exact(v, f)(p)

    res = rayproof.check_contains(fn, v, f, precision="float", random_points=100)
    assert res["findings"] == 0
    p = np.vstack(seen)
    finite = np.isfinite(p)
    assert (p[finite] == p[finite].astype(np.float32).astype(np.float64)).all()
    with pytest.raises(ValueError, match="precision"):
        rayproof.check_contains(fn, v, f, precision="half")


def test_keys_and_bad_arguments():
    v, f = cube()
    res = rayproof.check_contains(exact(v, f), v, f, points=np.array([[0.5, 0.5, 0.5]]))
    assert list(res) == ["points", "inside", "surface", "inside_called_outside", "outside_called_inside",
                         "false_surface", "surface_said_outside", "surface_said_inside", "surface_said_surface",
                         "rules_differ", "rules_differ_other", "winding_near_half", "garbage", "failures",
                         "invalid_points", "invalid_said_inside", "invalid_said_surface", "invalid_failures",
                         "findings", "rule", "sets", "reproducers", "notes", "judge_seconds", "contains_seconds",
                         "cost_ratio"]
    assert all(key in rayproof.check_contains.__doc__ for key in list(res)[:19])
    with pytest.raises(ValueError, match="rule"):
        rayproof.check_contains(exact(v, f), v, f, rule="majority")
    with pytest.raises(ValueError, match="not closed"):
        rayproof.check_contains(exact(v, f), *cube(top=False), rule="nonzero")
    with pytest.raises(ValueError, match="unknown point set"):
        rayproof.check_contains(exact(v, f), v, f, sets=["nope"])
    with pytest.raises(ValueError, match="triangles"):
        rayproof.check_contains(exact(v, f), v, f + 10)

    def interrupted(q):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        rayproof.check_contains(interrupted, v, f, random_points=10)
