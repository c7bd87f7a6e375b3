"""rayproof.check: a numpy Möller–Trumbore has false misses on exact edge and vertex hits; exact
classification wrapped as a user function has none; exceptions are reported with their case."""
import numpy as np
import pytest

import rayproof

TOUCH = {"interior", "edge", "vertex"}


def moller_trumbore(O, D, P0, P1, P2):
    """Vectorized Möller–Trumbore in the arrays' own precision (float32 here)."""
    with np.errstate(all="ignore"):
        e1, e2 = P1 - P0, P2 - P0
        p = np.cross(D, e2)
        det = np.einsum("ij,ij->i", e1, p)
        inv = 1 / det
        s = O - P0
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1)
        v = np.einsum("ij,ij->i", D, q) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
        return (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0), t


def certified(o, d, p0, p1, p2):
    """Per case: rayproof's own certified method behind the user-function interface."""
    r = rayproof.classify("triangle", o, d, np.concatenate([p0, p1, p2]), method="certified")
    c = r["classes"][0]
    hit = c in TOUCH or (c == "coplanar" and not np.isnan(r["t"][0]))
    return hit, float(r["t"][0])


EDGE_VERTEX = ["tri_edge", "tri_vertex"]


def test_numpy_moller_trumbore_has_false_misses_on_edges_and_vertices():
    res = rayproof.check(moller_trumbore, kind="triangle", vectorized=True, count=500, seed=1,
                         precision="float", families=EDGE_VERTEX)
    fam = res["families"]
    assert set(fam) == set(EDGE_VERTEX)
    misses = fam["tri_edge"]["false_misses"] + fam["tri_vertex"]["false_misses"]
    assert misses > 0
    assert res["total"]["false_misses"] == misses and res["total"]["cases"] == 1000
    assert res["failures"] == []
    # Each reproducer is a case line the function answered wrongly, with the exact answer.
    found = [r for r in res["reproducers"] if r["verdict"] == "false-miss"]
    assert found
    for r in found:
        tok = r["case"].split()
        assert tok[0] == "triangle" and len(tok) == 16
        assert r["got"].startswith("miss") and r["want"].split()[0] in TOUCH
        v = np.array([float(x) for x in tok[1:]], dtype=np.float32)
        hit, _ = moller_trumbore(*(v[None, i:i + 3] for i in range(0, 15, 3)))
        assert not hit[0]  # the reproducer really reproduces
    assert "tri_edge" in res["table"] and "false miss" in res["table"]


def test_every_triangle_family_runs():
    res = rayproof.check(moller_trumbore, vectorized=True, count=20, seed=3)
    names = {f for f in res["families"]}
    assert {"tri_generic", "tri_edge", "tri_vertex", "tri_coplanar", "tri_extreme_scale", "invalid"} <= names
    assert res["families"]["tri_generic"]["cases"] == 20
    assert res["families"]["tri_generic"]["t_count"] > 0


def test_certified_as_a_user_function_has_no_class_errors():
    res = rayproof.check(certified, kind="triangle", count=30, seed=2, precision="double")
    tot = res["total"]
    assert tot["cases"] > 0 and tot["failures"] == 0
    assert tot["false_hits"] == 0 and tot["false_misses"] == 0
    assert tot["t_count"] > 0 and tot["t_ulps_max"] <= 1
    assert [r for r in res["reproducers"] if r["verdict"] != "agree"] == []


def test_precision_float_passes_float32_arrays():
    seen = set()

    def f(o, d, p0, p1, p2):
        seen.update(a.dtype for a in (o, d, p0, p1, p2))
        assert o.shape == (3,)
        return False, None

    rayproof.check(f, count=2, families=["tri_generic"])
    assert seen == {np.dtype(np.float32)}


def test_sphere_arguments():
    def sphere(o, d, c, r):
        assert c.shape == (3,) and isinstance(r, float)
        oc = o - c
        a, b, k = d @ d, oc @ d, oc @ oc - r * r
        disc = b * b - a * k
        if disc < 0:
            return False, None
        s = np.sqrt(disc)
        t0, t1 = (-b - s) / a, (-b + s) / a
        return t1 >= 0, (t0 if t0 >= 0 else t1)

    res = rayproof.check(sphere, kind="sphere", count=20, precision="double", families=["sph_generic"])
    assert res["families"]["sph_generic"]["cases"] == 20 and res["failures"] == []


def test_exceptions_are_reported_with_their_case():
    def fragile(o, d, p0, p1, p2):
        if p0[0] < 0:
            raise ZeroDivisionError("negative x")
        return False, None

    res = rayproof.check(fragile, count=20, seed=5, families=["tri_generic"])
    fails = res["failures"]
    assert 0 < len(fails) < 20
    assert res["families"]["tri_generic"]["failures"] == len(fails)
    assert res["families"]["tri_generic"]["judged"] == 20 - len(fails)
    for fl in fails:
        assert "ZeroDivisionError" in fl["error"] and "negative x" in fl["error"]
        assert float(fl["case"].split()[7]) < 0  # p0.x of the case that raised


def test_vectorized_exceptions_are_found_case_by_case():
    def fragile(O, D, P0, P1, P2):
        if (P0[:, 0] < 0).any():
            raise ValueError("negative x in batch")
        return np.zeros(len(O), dtype=bool), np.full(len(O), np.nan)

    res = rayproof.check(fragile, vectorized=True, count=20, seed=5, families=["tri_generic"])
    bad = [fl for fl in res["failures"]]
    assert 0 < len(bad) < 20
    assert all(float(fl["case"].split()[7]) < 0 and "negative x" in fl["error"] for fl in bad)


def test_malformed_answers_raise_type_error():
    with pytest.raises(TypeError, match=r"returned 'yes' for the case `triangle "):
        rayproof.check(lambda *a: "yes", count=1, families=["tri_generic"])
    with pytest.raises(TypeError, match=r"hit array has shape \(3,\); expected \(5,\)"):
        rayproof.check(lambda O, *a: (np.zeros(3, bool), None), vectorized=True, count=5, families=["tri_generic"])


def test_keyboard_interrupt_propagates():
    def stop(*a):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        rayproof.check(stop, count=3, families=["tri_generic"])


def test_promises_and_progress():
    seen = []
    res = rayproof.check(moller_trumbore, vectorized=True, count=200, families=EDGE_VERTEX, watertight=True,
                         max_ulps=4, progress=lambda fam, done, total: seen.append((fam, done, total)))
    assert seen == [("tri_edge", 1, 2), ("tri_vertex", 2, 2)]
    promises = {p["promise"]: p for p in res["promises"]}
    assert not promises["watertight"]["kept"] and not res["promises_kept"]
    fm = res["families"]["tri_edge"]["false_misses"] + res["families"]["tri_vertex"]["false_misses"]
    assert promises["watertight"]["violations"] == fm > 0
    assert "max-ulps 4" in promises
    res = rayproof.check(certified, count=10, precision="double", exact_class=True, watertight=True, max_ulps=1)
    assert res["promises_kept"] and all(p["kept"] for p in res["promises"])


def test_the_example_finds_false_misses():
    import pathlib, subprocess, sys
    example = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python" / "numpy_mt_check.py"
    out = subprocess.run([sys.executable, str(example)], capture_output=True, text=True, check=True).stdout
    assert "'watertight', 'kept': False" in out
    assert "-> miss - -, exact:" in out


def test_failures_are_not_class_errors_nor_reproducers():
    def fragile(O, D, P0, P1, P2):
        if (P0[:, 0] < 0).any():
            raise ValueError("negative x in batch")
        return np.zeros(len(O), dtype=bool), None  # never a hit: false misses only where exact touches

    res = rayproof.check(fragile, vectorized=True, count=40, seed=5, precision="double",
                         families=["tri_interior_exact"])
    fam = res["families"]["tri_interior_exact"]
    raised = len(res["failures"])
    assert 0 < raised < 40 and fam["failures"] == raised
    # tri_interior_exact cases all touch (double: no rounding): every judged case is a false miss.
    assert fam["false_misses"] == fam["judged"] == 40 - raised
    assert all(r["verdict"] == "false-miss" for r in res["reproducers"])


def test_barycentrics_are_judged():
    def mt_bary(O, D, P0, P1, P2, swap=False):
        hit, t = moller_trumbore(O, D, P0, P1, P2)
        with np.errstate(all="ignore"):
            e1, e2, s = P1 - P0, P2 - P0, O - P0
            p, q = np.cross(D, e2), np.cross(s, e1)
            det = np.einsum("ij,ij->i", e1, p)
            u, v = np.einsum("ij,ij->i", s, p) / det, np.einsum("ij,ij->i", D, q) / det
        return (hit, t, v, u) if swap else (hit, t, u, v)

    kw = dict(vectorized=True, count=40, precision="double", families=["tri_interior_exact"])
    good = rayproof.check(mt_bary, **kw)["families"]["tri_interior_exact"]
    assert good["bary_count"] > 0 and good["bary_error_max"] < 1e-6
    bad = rayproof.check(lambda *a: mt_bary(*a, swap=True), **kw)["families"]["tri_interior_exact"]
    assert bad["bary_count"] == good["bary_count"] and bad["bary_error_max"] > 1e-3
    # Without barycentrics nothing is judged.
    assert rayproof.check(moller_trumbore, **kw)["families"]["tri_interior_exact"]["bary_count"] == 0


def test_t_errors_are_worded_as_report_and_the_cli_word_them():
    """A t three times too large plus one is 'leading bits wrong', not a raw 19-digit ulp count (the table is the CLI
    check's; its NaN wording is tested in C++, CheckText.TErrorsAreWordedAsReportWordsThem)."""
    def far(o, d, p0, p1, p2):
        r = rayproof.classify("triangle", o, d, np.concatenate([p0, p1, p2]), method="certified")
        c = r["classes"][0]
        hit = c in TOUCH or (c == "coplanar" and not np.isnan(r["t"][0]))
        return hit, 3 * float(r["t"][0]) + 1

    res = rayproof.check(far, count=20, seed=4, precision="double", families=["tri_generic"], minimize=False)
    assert res["total"]["t_ulps_max"] > 10**15
    assert "(leading bits wrong)" in res["table"]
    assert not any(len(tok) > 12 and tok.isdigit() for tok in res["table"].split()), res["table"]
    assert "t max" in res["table"] and "> 1 ulp" in res["table"]  # the CLI check's columns
    worded = [r["t_error"] for r in res["reproducers"] if r["verdict"] == "agree"]
    assert worded and all(w.endswith("(leading bits wrong)") for w in worded)
    assert all(r["t_error"] is None for r in res["reproducers"] if r["verdict"] != "agree")


# --- triangle pairs: kind "tritri", f(p0, p1, p2, q0, q1, q2) -> bool --------------------------------

PAIR_FAMILIES = ["tritri_shared_vertex", "tritri_vertex_on_face", "tritri_far_apart"]
MEETS = {"crossing", "touching", "coplanar_overlap", "coplanar_touching"}


def _gd_example():
    import importlib.util, pathlib
    path = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python" / "tritri_guigue_devillers.py"
    spec = importlib.util.spec_from_file_location("tritri_gd", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_pair_kernels_always_and_never_split_the_judged_pairs():
    """'Always meets' is wrong exactly on the disjoint pairs, 'never' exactly on the meeting ones."""
    args = dict(kind="tritri", count=60, seed=3, precision="double", families=PAIR_FAMILIES)
    yes = rayproof.check(lambda *p: True, **args)
    no = rayproof.check(lambda *p: False, **args)
    for fam in PAIR_FAMILIES:
        y, n = yes["families"][fam], no["families"][fam]
        assert y["cases"] == n["cases"] > 0
        assert y["false_misses"] == 0 and n["false_hits"] == 0
        assert y["false_hits"] + n["false_misses"] == y["cases"]
    assert no["families"]["tritri_vertex_on_face"]["false_misses"] == no["families"]["tritri_vertex_on_face"]["cases"]
    assert yes["families"]["tritri_far_apart"]["false_hits"] == yes["families"]["tritri_far_apart"]["cases"]
    assert "false meets" in yes["table"] and "false disjoint" in yes["table"]


def test_pair_kernel_gets_six_points_in_its_precision():
    seen = []

    def f(*pts):
        seen.append((len(pts), [np.asarray(p).dtype for p in pts], [np.asarray(p).shape for p in pts]))
        return False

    rayproof.check(f, kind="tritri", count=2, precision="float", families=["tritri_crossing"])
    assert seen and all(n == 6 and all(d == np.float32 for d in dt) and all(s == (3,) for s in sh) for n, dt, sh in seen)
    with pytest.raises(TypeError, match="expected a bool"):
        rayproof.check(lambda *p: (True, 1.0), kind="tritri", count=2, families=["tritri_crossing"])


def test_the_guigue_devillers_example_misses_contacts_and_its_reproducers_reproduce():
    gd = _gd_example()

    def f(*pts):  # numpy arrays of 3 -> the example's tuples of Python floats
        p0, p1, p2, q0, q1, q2 = (tuple(float(x) for x in p) for p in pts)
        return gd.meets([p0, p1, p2], [q0, q1, q2])

    res = rayproof.check(f, kind="tritri", count=200, seed=1, precision="double", families=PAIR_FAMILIES,
                         minimize=False)
    assert res["failures"] == []
    misses = [r for r in res["reproducers"] if r["verdict"] == "false-miss"]
    assert len(misses) > 0 or res["total"]["false_misses"] == 0
    for r in misses:
        v = [float(x) for x in r["case"].split()[1:]]
        assert r["case"].split()[0] == "tritri" and len(v) == 18
        assert r["got"] == "miss" and r["want"] in MEETS
        assert not gd.meets([tuple(v[0:3]), tuple(v[3:6]), tuple(v[6:9])], [tuple(v[9:12]), tuple(v[12:15]), tuple(v[15:18])])
