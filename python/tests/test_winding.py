"""Mesh.contains and Mesh.winding on meshes that are not closed: the generalized winding number with
its bound against a brute-force sum of solid angles in numpy (float64) and closed forms (the centre
of an open box), surface points, the exact tie w = 1/2, closed meshes keeping their integers."""
import numpy as np
import pytest

import rayproof

CUBE_V = np.array([[(-1, 1)[i & 1], (-1, 1)[i >> 1 & 1], (-1, 1)[i >> 2 & 1]] for i in range(8)], dtype=np.float64)
# Two triangles per face, outward: -x, +x, -y, +y, -z, +z.
FACES = [[[0, 4, 2], [2, 4, 6]], [[1, 3, 5], [3, 7, 5]], [[0, 1, 4], [1, 5, 4]],
         [[2, 6, 3], [3, 6, 7]], [[0, 2, 1], [1, 2, 3]], [[4, 5, 6], [5, 7, 6]]]


def box(faces):
    return rayproof.Mesh(CUBE_V, np.array([t for f in faces for t in FACES[f]], dtype=np.uint32))


def brute_winding(v, t, p):
    """Sum of Van Oosterom-Strackee solid angles / 4 pi, in float64 (no bound)."""
    a, b, c = (v[t[:, k]][None, :, :] - p[:, None, :] for k in range(3))
    la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
    n = np.einsum("ptk,ptk->pt", a, np.cross(b, c))
    d = la * lb * lc + np.einsum("ptk,ptk->pt", a, b) * lc + np.einsum("ptk,ptk->pt", b, c) * la \
        + np.einsum("ptk,ptk->pt", c, a) * lb
    return (2 * np.arctan2(n, d)).sum(axis=1) / (4 * np.pi)


def test_open_box_centre_and_far_points():
    m = box([0, 1, 2, 3, 4])  # no top
    assert not m.closed and not m.oriented and m.rule == "winding"
    w, bound = m.winding(np.array([[0.0, 0, 0], [0, 0, 50]]))
    assert w.dtype == np.float64 and bound.dtype == np.float64
    assert abs(w[0] - 5 / 6) <= bound[0] <= 1e-6
    assert abs(w[1]) <= 1e-3 and bound[1] <= 1e-6
    got = m.contains(np.array([[0.0, 0, 0], [0, 0, 50], [0, 0, -1], [0.5, 0.5, 1.0]]))
    np.testing.assert_array_equal(got, [rayproof.INSIDE, rayproof.OUTSIDE, rayproof.SURFACE, rayproof.OUTSIDE])


def test_random_points_against_numpy_brute_force():
    faces = [0, 1, 2, 3, 4]
    tris = np.array([t for f in faces for t in FACES[f]])
    tris = np.delete(tris, 3, axis=0)  # and a hole in the side
    m = rayproof.Mesh(CUBE_V, tris.astype(np.uint32))
    rng = np.random.default_rng(4)
    p = rng.uniform(-1.5, 1.5, size=(400, 3))
    w, bound = m.winding(p, tolerance=1e-9)
    ref = brute_winding(CUBE_V, tris, p)
    # The numpy sum errs by a few ulps per triangle: 1e-13 covers it.
    assert np.all(np.abs(w - ref) <= bound + 1e-13)
    assert np.all(bound <= 1e-9)
    side = m.contains(p)
    decided = np.abs(ref - 0.5) > 1e-9
    np.testing.assert_array_equal(side[decided], np.where(ref[decided] > 0.5, rayproof.INSIDE, rayproof.OUTSIDE))
    assert (side == rayproof.INSIDE).sum() > 50


def test_surface_invalid_and_the_exact_tie():
    m = box([0, 2, 4])  # three faces meeting at (-1, -1, -1): w = 1/2 exactly at the centre
    w, bound = m.winding(np.array([[0.0, 0, 0], [-1, 0.5, 0.25], [np.nan, 0, 0]]))
    assert abs(w[0] - 0.5) <= bound[0]
    assert np.isnan(w[1]) and bound[1] == 0  # on a face: surface
    assert np.isnan(w[2]) and np.isinf(bound[2])
    side = m.contains(np.array([[0.0, 0, 0], [-1, 0.5, 0.25], [np.nan, 0, 0], [-1e-9, -1e-9, -1e-9]]))
    np.testing.assert_array_equal(side, [rayproof.OUTSIDE, rayproof.SURFACE, rayproof.INVALID, rayproof.INSIDE])


def test_closed_mesh_keeps_integers_and_with_bound():
    m = box([0, 1, 2, 3, 4, 5])
    assert m.closed and m.oriented and m.rule == "nonzero"
    w = m.winding(np.array([[0.0, 0, 0], [3, 0, 0]]))
    assert w.dtype == np.int32 and list(w) == [1, 0]
    wf, bound = m.winding(np.array([[0.0, 0, 0], [3, 0, 0]]), with_bound=True)
    assert list(wf) == [1.0, 0.0] and list(bound) == [0.0, 0.0]
    assert m.contains([0.1, 0.2, 0.3], rule="winding")[0] == rayproof.INSIDE
    with pytest.raises(ValueError, match="tolerance"):
        m.winding(np.zeros((1, 3)), tolerance=0)
