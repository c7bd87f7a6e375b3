"""Bad shapes, dtypes and names: Python exceptions that name the argument."""
import numpy as np
import pytest

import rayproof

TRI = [2, 2, 2, 3, 7, -1, 0, 9, -4]


@pytest.mark.parametrize(
    "args, exc, words",
    [
        (("triangle", np.zeros((4, 2)), [1, 1, 1], TRI), ValueError, "origins: expected shape (n, 3) or (3,), got (4, 2)"),
        (("triangle", np.zeros((4, 3)), np.ones((5, 3)), TRI), ValueError, "directions: 5 rows, but origins has 4"),
        (("triangle", [0, 0, 0], [1, 1, 1], TRI[:6]), ValueError, "prims: expected shape (n, 9) or (9,), got (6,)"),
        (("triangle", [0, 0, 0], [1, 1, 1], np.zeros((2, 3, 9))), ValueError, "prims: expected shape"),
        (("triangle", np.zeros(3, dtype=complex), [1, 1, 1], TRI), TypeError, "origins: expected an array of real numbers"),
        (("triangle", [0, 0, 0], ["a", "b", "c"], TRI), TypeError, "directions: expected an array of real numbers"),
        (("triangle", [0, 0, 0], np.ones(3, dtype=bool), TRI), TypeError, "directions: expected an array of real numbers (float or integer dtype), got dtype bool"),
        (("triangle", [0, 0, 0], [1, 1, 1], None), TypeError, "prims: expected an array, got None"),
        (("cone", [0, 0, 0], [1, 1, 1], TRI), ValueError, "kind: unknown kind 'cone'"),
    ],
)
def test_classify_errors(args, exc, words):
    with pytest.raises(exc) as e:
        rayproof.classify(*args)
    assert words in str(e.value)


def test_unknown_method_and_unsupported_kind():
    with pytest.raises(ValueError, match="method: unknown method 'fast'.*certified"):
        rayproof.classify("triangle", [0, 0, 0], [1, 1, 1], TRI, method="fast")
    with pytest.raises(ValueError, match="method: 'watertight-float' does not answer sphere cases"):
        rayproof.classify("sphere", [0, 0, 0], [1, 1, 1], [5, 0, 0, 1], method="watertight-float")


V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float64)
I = np.array([[0, 1, 2]], dtype=np.uint32)


@pytest.mark.parametrize(
    "v, i, exc, words",
    [
        (V[:, :2], I, ValueError, "vertices: expected shape (n, 3), got (3, 2)"),
        (V.astype(np.complex64), I, TypeError, "vertices: expected an array of real numbers"),
        (V, I.astype(np.float32), TypeError, "indices: expected an array of integers"),
        (V, np.array([[0, 1, 3]]), ValueError, "indices: row 0 has vertex index 3 outside [0, 3)"),
        (V, np.array([[0, -1, 2]]), ValueError, "indices: row 0 has vertex index -1 outside [0, 3)"),
        (np.array([[0, 0, 0], [1, np.inf, 0], [0, 1, 0]]), I, ValueError,
         "mesh: MeshCaster: vertex 1 (used by triangle 0) has a NaN or infinite coordinate"),
        (V, I.ravel(), ValueError, "indices: expected shape (n, 3), got (3,)"),
    ],
)
def test_mesh_errors(v, i, exc, words):
    with pytest.raises(exc) as e:
        rayproof.Mesh(v, i)
    assert words in str(e.value)


def test_cast_errors():
    m = rayproof.Mesh(V, I)
    with pytest.raises(ValueError, match=r"method: 'double' is not a mesh casting method \(float, robust, certified\)"):
        m.closest([0, 0, 1], [0, 0, -1], method="double")
    with pytest.raises(ValueError, match="directions: 2 rows, but origins has 3"):
        m.any(np.zeros((3, 3)), np.ones((2, 3)))


def test_check_argument_errors():
    f = lambda o, d, p0, p1, p2: (False, None)  # noqa: E731
    with pytest.raises(TypeError, match="f: expected a callable"):
        rayproof.check(3)
    with pytest.raises(ValueError, match="precision: expected 'float' or 'double', got 'half'"):
        rayproof.check(f, precision="half")
    with pytest.raises(ValueError, match="kind: unknown kind"):
        rayproof.check(f, kind="torus")
    with pytest.raises(ValueError, match="families: unknown family 'tri_nope'"):
        rayproof.check(f, families=["tri_nope"])
    with pytest.raises(ValueError, match="families: 'sph_generic' is a sphere family, not triangle"):
        rayproof.check(f, families=["sph_generic"])
    with pytest.raises(ValueError, match="count: must be at least 1"):
        rayproof.check(f, count=0)


def test_empty_mesh_and_unused_non_finite_vertices():
    empty = rayproof.Mesh(V, np.zeros((0, 3), dtype=np.int64))
    assert empty.num_triangles == 0
    r = empty.closest([0, 0, 1], [0, 0, -1])
    assert not r["hit"][0] and r["prim"][0] == -1 and r["classes"][0] == "miss"
    # A vertex no triangle uses is not checked (include/rayproof/scene/mesh_caster.h).
    m = rayproof.Mesh(np.vstack([V, [[np.nan, 0, 0]]]), I)
    assert m.closest([0.25, 0.25, 1], [0, 0, -1], method="certified")["classes"][0] == "interior"


def test_mesh_from_lists():
    m = rayproof.Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])  # int64 vertices, converted exactly
    assert m.closest([0.25, 0.25, 1], [0, 0, -1], method="certified")["t"][0] == 1.0
