"""rayproof.check_caster: whole casters (a Python function over arrays of rays) judged on a mesh.
A numpy Möller–Trumbore with strict edge tests leaks; rayproof's own casters keep their promises;
a function that raises, or returns garbage, is reported and the run goes on."""
import numpy as np
import pytest

import rayproof


def octahedron():
    v = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=np.float64)
    f = []
    for sx, a in ((1, 0), (-1, 1)):
        for sy, b in ((1, 2), (-1, 3)):
            for sz, c in ((1, 4), (-1, 5)):
                f.append([a, b, c] if sx * sy * sz > 0 else [a, c, b])
    return v * np.array([1.0, 1.25, 0.75]), np.array(f, dtype=np.int64)


def mt_caster(vertices, triangles, strict):
    """Möller–Trumbore over every triangle in float64, vectorized over rays x triangles."""
    P0, P1, P2 = (vertices[triangles[:, k]] for k in range(3))
    E1, E2 = P1 - P0, P2 - P0

    def fn(O, D):
        with np.errstate(all="ignore"):
            p = np.cross(D[:, None, :], E2[None, :, :])
            det = np.einsum("ntk,tk->nt", p, E1)
            inv = 1.0 / det
            s = O[:, None, :] - P0[None, :, :]
            u = np.einsum("ntk,ntk->nt", s, p) * inv
            q = np.cross(s, E1[None, :, :])
            v = np.einsum("nk,ntk->nt", D, q) * inv
            t = np.einsum("tk,ntk->nt", E2, q) * inv
            if strict:
                ok = (det != 0) & (u > 0) & (v > 0) & (u + v < 1) & (t > 0)
            else:
                ok = (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
            t = np.where(ok, t, np.inf)
            tri = np.argmin(t, axis=1)
            best = t[np.arange(len(O)), tri]
            return best, np.where(np.isfinite(best), tri, -1)

    return fn


def test_strict_numpy_caster_leaks_with_reproducers():
    v, f = octahedron()
    res = rayproof.check_caster(mt_caster(v, f, strict=True), v, f, random_rays=300, mesh_name="octa")
    assert res["rays"] == sum(s["rays"] for s in res["sets"].values())
    assert res["false_miss"] > 0
    assert res["sets"]["leak"]["findings"] > 0
    leaks = [r for r in res["reproducers"] if r.startswith("false-miss")]
    assert leaks and all("mesh=octa" in r and "caster: tri -1 t inf" in r for r in leaks)
    assert res["findings"] >= res["false_miss"]


def test_rayproof_robust_caster_has_no_false_miss():
    v, f = octahedron()
    mesh = rayproof.Mesh(v, f)

    def robust(O, D):
        h = mesh.closest(O, D, method="robust", tmin=np.nextafter(0, 1))
        return np.where(h["hit"], h["t"], np.inf), h["prim"]

    res = rayproof.check_caster(robust, v, f, random_rays=300, precision="float", sets=["leak", "random", "invalid"])
    assert res["false_miss"] == 0 and res["garbage"] == 0 and res["caster_failures"] == 0
    assert res["invalid_hit"] == 0 and res["invalid_failures"] == 0
    assert res["hits"] > 0


def test_raising_function_is_reported_and_the_run_goes_on():
    v, f = octahedron()

    def boom(O, D):
        raise RuntimeError("no BVH today")

    res = rayproof.check_caster(boom, v, f, random_rays=100)
    assert res["caster_failures"] + res["invalid_failures"] == res["rays"]
    assert res["invalid_failures"] == res["invalid_rays"] > 0
    assert any("no BVH today" in n for n in res["notes"])

    exact = mt_caster(v, f, strict=False)

    def nan_hater(O, D):
        if not np.isfinite(O).all() or not np.isfinite(D).all():
            raise ValueError("NaN ray")
        return exact(O, D)

    res = rayproof.check_caster(nan_hater, v, f, random_rays=100, batch=1, sets=["random", "invalid"])
    assert res["caster_failures"] == 0
    assert res["invalid_failures"] > 0
    assert res["invalid_failures"] < res["invalid_rays"]  # zero-direction rays are finite: answered
    assert res["sets"]["random"]["rays"] == 100


def test_garbage_answers_are_counted():
    v, f = octahedron()

    def shapeless(O, D):
        return np.zeros(len(O) + 1), np.zeros(len(O) + 1, dtype=np.int64)

    res = rayproof.check_caster(shapeless, v, f, random_rays=50, sets=["random"])
    assert res["caster_failures"] == 50
    assert any("shape" in n for n in res["notes"])

    def nan_t(O, D):
        return np.full(len(O), np.nan), np.zeros(len(O), dtype=np.int64)

    res = rayproof.check_caster(nan_t, v, f, random_rays=50, sets=["random"])
    assert res["garbage"] == 50
    assert all(r.startswith("garbage") for r in res["reproducers"])


def test_any_hit_function_is_judged():
    v, f = octahedron()
    closest = mt_caster(v, f, strict=False)
    res = rayproof.check_caster(closest, v, f, any_fn=lambda O, D: np.zeros(len(O), dtype=bool),
                                random_rays=200, sets=["random"])
    assert res["any_rays"] == 200
    assert res["any_false_miss"] + res["any_coplanar_miss"] == res["hits"] > 0


def test_own_rays_and_bad_arguments():
    v, f = octahedron()
    fn = mt_caster(v, f, strict=False)
    O = np.array([[0.0, 0.0, 0.0], [5.0, 5.0, 5.0]])
    D = np.array([[1.0, 1.0, 1.0], [1.0, 0.0, 0.0]])
    res = rayproof.check_caster(fn, v, f, rays=(O, D))
    assert res["rays"] == 2 and res["hits"] == 1 and res["findings"] == 0
    # The dict's keys, in order: every count (the keys of `rayproof check --caster --json`), then
    # the per-set counts, reproducers and notes.
    assert list(res) == ["rays", "hits", "false_miss", "coplanar_miss", "false_hit", "wrong_triangle",
                         "wrong_triangle_within_1ulp", "t_over_1ulp", "max_ulps", "garbage", "caster_failures",
                         "any_rays", "any_false_miss", "any_false_hit", "any_coplanar_miss", "invalid_rays",
                         "invalid_hit", "invalid_failures", "findings", "sets", "reproducers", "notes"]
    assert all(key in rayproof.check_caster.__doc__ for key in list(res)[:19])
    with pytest.raises(ValueError, match="precision"):
        rayproof.check_caster(fn, v, f, precision="half")
    with pytest.raises(ValueError, match="triangles"):
        rayproof.check_caster(fn, v, f + 10)
    with pytest.raises(ValueError, match="unknown ray set"):
        rayproof.check_caster(fn, v, f, sets=["nope"])
    with pytest.raises(TypeError):
        rayproof.check_caster(fn, v.astype(str), f)


def test_interrupt_propagates_and_odd_meshes_are_handled():
    v, f = octahedron()

    def interrupted(O, D):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        rayproof.check_caster(interrupted, v, f, random_rays=10)
    miss = lambda O, D: (np.full(len(O), np.inf), np.full(len(O), -1))
    empty = rayproof.check_caster(miss, np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), random_rays=10)
    assert empty["hits"] == 0 and empty["findings"] == 0
    one = rayproof.check_caster(miss, v, f[:1], random_rays=50)  # an open mesh: no leak rays
    assert one["sets"]["leak"]["rays"] == 0 and any(n.startswith("leak:") for n in one["notes"])
    assert one["false_miss"] + one["coplanar_miss"] == one["hits"] > 0
    with pytest.raises(ValueError, match="NaN"):
        rayproof.check_caster(miss, np.where(v == 1, np.nan, v), f)
