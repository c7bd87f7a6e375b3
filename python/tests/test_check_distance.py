"""rayproof.check_distance: distance functions (a Python function over an array of points) judged on
a mesh. rayproof's own distances get no finding; a distance off by a relative 1e-9 is forgiven by
rel_tol and not without it; flipped signs, nonzero surface distances, numbers at NaN points and
raising functions get exactly the expected counts. Closest points and triangles (a tuple or a dict
of columns): rayproof's own have no finding, wrong ones are counted; precision='float' judges the
mesh and the points rounded to float, in float ulps."""
import numpy as np
import pytest

import rayproof


def cube():
    v = np.array([[i & 1, (i >> 1) & 1, (i >> 2) & 1] for i in range(8)], dtype=np.float64)
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    f = [t for q in quads for t in ([q[0], q[1], q[2]], [q[0], q[2], q[3]])]
    return v, np.array(f, dtype=np.int64)


def exact(v, f, signed):
    mesh = rayproof.Mesh(v, f)

    def fn(p):
        return mesh.signed_distance(p) if signed else mesh.distance(p)

    return fn


def test_rayproofs_own_distances_have_no_finding():
    v, f = cube()
    for signed in (False, True):
        res = rayproof.check_distance(exact(v, f, signed), v, f, signed=signed, random_points=200)
        assert res["findings"] == 0, res["reproducers"]
        assert res["max_ulps"] == 0 and res["surface"] > 0 and res["invalid_points"] == 10
        assert res["points"] == sum(s["points"] for s in res["sets"].values())


def test_relative_error_sign_surface_and_invalid():
    v, f = cube()
    p = np.array([[0.5, 0.5, 0.5], [2.0, 0.5, 0.5], [1.0, 0.5, 0.5], [np.nan, 0, 0]])
    res = rayproof.check_distance(lambda q: np.array([-0.5, 1.0, 0.0, np.nan]) * (1 + 1e-9), v, f, signed=True,
                                  points=p)
    assert (res["over_1ulp"], res["over_tolerance"], res["findings"]) == (2, 2, 2)
    res = rayproof.check_distance(lambda q: np.array([-0.5, 1.0, 0.0, np.nan]) * (1 + 1e-9), v, f, signed=True,
                                  rel_tol=1e-8, points=p)
    assert (res["over_1ulp"], res["over_tolerance"], res["findings"]) == (2, 0, 0)
    assert res["max_rel_error"] == pytest.approx(1e-9, rel=1e-3)
    res = rayproof.check_distance(lambda q: np.array([0.5, -1.0, 1e-300, 0.0]), v, f, signed=True, points=p)
    assert (res["wrong_sign"], res["surface_nonzero"], res["invalid_number"]) == (2, 1, 1)
    assert any(r.startswith("wrong-sign set=user mesh=mesh point 0.5 0.5 0.5 exact: -0.5") for r in res["reproducers"])
    res = rayproof.check_distance(lambda q: np.array([0.5, -1.0, 0.0, np.nan]), v, f, points=p)  # unsigned
    assert res["garbage"] == 1


def test_raising_and_bad_arguments():
    v, f = cube()

    def boom(q):
        raise RuntimeError("no tree today")

    res = rayproof.check_distance(boom, v, f, random_points=20, batch=7)
    assert res["failures"] + res["invalid_failures"] == res["points"]
    assert any("no tree today" in n for n in res["notes"])
    assert all(key in rayproof.check_distance.__doc__ for key in list(res)[:18])
    with pytest.raises(ValueError, match="rel_tol"):
        rayproof.check_distance(boom, v, f, rel_tol=-1)
    with pytest.raises(ValueError, match="unknown point set"):
        rayproof.check_distance(boom, v, f, sets=["nope"])


def exact_columns(v, f):
    mesh = rayproof.Mesh(v, f)

    def fn(p):
        c = mesh.closest_points(p)
        return c["distance"], c["points"], c["triangles"]

    return fn, mesh.closest_points


def test_closest_points_and_triangles():
    v, f = cube()
    for fn in exact_columns(v, f):  # a tuple, and Mesh.closest_points' dict
        res = rayproof.check_distance(fn, v, f, random_points=100)
        assert res["findings"] == 0, res["reproducers"]
        assert res["closest_points"] == res["triangle_ids"] == res["points"] - res["invalid_points"]
    p = np.array([[0.5, 0.5, 2.0], [0.5, 0.5, 3.0]])
    answers = {"distance": np.array([1.0, 2.0]), "points": np.array([[0.5, 0.5, 1.25], [0, 0, 1]]),
               "triangles": np.array([0, 2])}
    res = rayproof.check_distance(lambda q: answers, v, f, points=p)
    assert (res["closest_off_mesh"], res["closest_not_nearest"], res["wrong_triangle"], res["findings"]) == (1, 1, 1, 3)
    res = rayproof.check_distance(lambda q: (answers["distance"], answers["points"]), v, f, points=p)
    assert (res["closest_points"], res["triangle_ids"], res["findings"]) == (2, 0, 2)
    res = rayproof.check_distance(lambda q: (answers["distance"], np.zeros((2, 2))), v, f, points=p)
    assert res["failures"] == 2 and any("shape" in n for n in res["notes"])
    res = rayproof.check_distance(lambda q: {"dist": answers["distance"]}, v, f, points=p)
    assert res["failures"] == 2 and any("'dist'" in n for n in res["notes"])


NEAR = ["vertex", "edge", "face", "nudged", "thin", "random"]  # not `far`: its distances overflow * (1 + 1e-12)


def test_float_precision():
    v, f = cube()
    v = v * 0.1
    vf = v.astype(np.float32).astype(np.float64)
    mesh = rayproof.Mesh(vf, f)
    res = rayproof.check_distance(lambda q: mesh.distance(q) * (1 + 1e-12), v, f, precision="float", sets=NEAR)
    assert res["findings"] == 0 and res["precision"] == "float", res["reproducers"]
    res = rayproof.check_distance(lambda q: mesh.distance(q) * (1 + 1e-12), vf, f, sets=NEAR)
    assert res["over_tolerance"] > 0 and res["precision"] == "double"
    with pytest.raises(ValueError, match="precision"):
        rayproof.check_distance(lambda q: q[:, 0], v, f, precision="half")
    with pytest.raises(ValueError, match="float's range"):
        rayproof.check_distance(lambda q: q[:, 0], v * 1e300, f, precision="float")
