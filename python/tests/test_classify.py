"""rayproof.classify against `rayproof classify` and the expected answers of data/sample.txt."""
import numpy as np
import pytest

import rayproof
from conftest import DATA, classify_cases, parse_result, run_cli, same_float


def test_methods_lists_the_registry():
    names = [m["name"] for m in rayproof.methods()]
    for name in ("float", "double", "robust", "certified", "exact"):
        assert name in names
    cert = next(m for m in rayproof.methods() if m["name"] == "certified")
    assert cert["precision"] == "double"
    assert set(cert["kinds"]) == {"plane", "sphere", "ellipsoid", "triangle", "box", "disk", "tritri"}
    assert next(m for m in rayproof.methods() if m["name"] == "float")["precision"] == "float"


@pytest.mark.parametrize("method", ["exact", "certified", "float", "double", "robust", "cramer-float"])
def test_equals_the_command_line_tool(sample, method):
    classes, t, t2 = classify_cases(sample, method)
    partial = None in classes  # the tool exits 1 when it answered `error` for a kind
    lines = run_cli("classify", "--method", method, DATA / "sample.txt", status=1 if partial else 0)
    want = [parse_result(line) for line in lines]
    assert len(want) == len(sample)
    # The tool answers `error - -` for a kind the method does not answer; classify() refuses those.
    want = [("error", np.nan, np.nan) if c is None else w for c, w in zip(classes, want)]
    classes = ["error" if c is None else c for c in classes]
    assert classes == [w[0] for w in want]
    assert same_float(t, [w[1] for w in want]).all()
    assert same_float(t2, [w[2] for w in want]).all()


@pytest.mark.parametrize("method", ["exact", "certified"])
def test_exact_and_certified_give_the_expected_answers(sample, method):
    classes, t, t2 = classify_cases(sample, method)
    want = [parse_result(line) for line in (DATA / "sample.expected").read_text().splitlines() if line.strip()]
    assert classes == [w[0] for w in want]
    assert same_float(t, [w[1] for w in want]).all()
    assert same_float(t2, [w[2] for w in want]).all()


def test_worked_examples_and_broadcasting():
    r = rayproof.classify("ellipsoid", [0, 0, 0], [1, 1, 0], [2, 2, 0, 2, 1, 2], method="exact")
    assert list(r["classes"]) == ["hit"]
    assert r["t"][0] == 1.105572809000084 and r["t2"][0] == 2.8944271909999157
    # One triangle broadcast against three rays; codes index CLASS_NAMES.
    o = np.array([[0, 0, 0], [0, 0, 1], [0, 0, 0]], dtype=np.float32)
    d = np.array([[1, 1, 1], [1, 1, 0], [-1, -1, -1]], dtype=np.float32)
    r = rayproof.classify("triangle", o, d, [2, 2, 2, 3, 7, -1, 0, 9, -4])
    assert list(r["classes"]) == ["vertex", "miss", "behind"]
    assert [rayproof.CLASS_NAMES[c] for c in r["codes"]] == list(r["classes"])
    assert r["t"][0] == 2.0 and np.isnan(r["t2"][0]) and r["t"][2] == -2.0
    assert np.isnan(r["t"][1])


def test_float_methods_see_float_rounded_inputs():
    # 0.1 is not a float: the float method answers for float(0.1), like `rayproof classify`.
    o, d, p = [0.1, 0.2, -1.0], [0, 0, 1], [0, 0, 0.3, 0, 0, 1, 0.7]
    f = rayproof.classify("disk", o, d, p, method="float")
    e = rayproof.classify("disk", np.float32(o), np.float32(d), np.float32(p), method="exact")
    assert f["classes"][0] == e["classes"][0] == "hit"
    assert np.float32(f["t"][0]) == np.float32(e["t"][0])


def test_invalid_input_is_a_class_not_an_error():
    r = rayproof.classify("sphere", [[np.nan, 0, 0], [0, 0, 0]], [[1, 0, 0], [0, 0, 0]], [5, 0, 0, 1], method="certified")
    assert list(r["classes"]) == ["invalid", "invalid"]


# --- triangle pairs: rayproof.classify_pairs(a, b, method) against `rayproof classify` on tritri lines ------


def _pair_cases(tmp_path, family, count=40, seed=5):
    path = tmp_path / f"{family}.txt"
    path.write_text("\n".join(run_cli("gen", family, "--count", count, "--seed", seed)) + "\n")
    rows = []
    for line in path.read_text().splitlines():
        tok = line.split("#")[0].split()
        if tok and tok[0] == "tritri":
            rows.append([float.fromhex(x) if "x" in x.lower() else float(x) for x in tok[1:]])
    return path, np.array(rows, dtype=np.float64)


@pytest.mark.parametrize("method", ["certified", "exact", "moller-float", "gd-double"])
@pytest.mark.parametrize("family", ["tritri_shared_vertex", "tritri_coplanar_touching", "tritri_random"])
def test_classify_pairs_equals_the_command_line_tool(tmp_path, method, family):
    path, v = _pair_cases(tmp_path, family)
    assert v.shape[1] == 18 and len(v) > 0
    got = rayproof.classify_pairs(v[:, :9].reshape(-1, 3, 3), v[:, 9:], method=method)
    want = [line.split()[0] for line in run_cli("classify", "--method", method, path)]
    assert list(got["classes"]) == want
    assert [rayproof.CLASS_NAMES[c] for c in got["codes"]] == want


def test_classify_pairs_classes_a_known_pair_and_broadcasts():
    a = np.array([[0, 0, 0], [4, 0, 0], [0, 4, 0]])
    touching = np.array([[1, 1, 0], [1, 1, 1], [2, 1, 1]])  # a vertex on a's face, the rest above
    crossing = np.array([[1, 1, -1], [1, 1, 1], [2, 1, 1]])
    far = touching + [0, 0, 5]
    res = rayproof.classify_pairs(a, np.stack([touching, crossing, far]))
    assert list(res["classes"]) == ["touching", "crossing", "disjoint"]
    assert list(rayproof.classify_pairs(a, np.stack([touching, far]), method="moller-double")["classes"]) == ["hit", "miss"]
    assert list(rayproof.classify_pairs(a, [[0, 0, 0], [1, 1, 1], [2, 2, 2]])["classes"]) == ["degenerate"]
    assert list(rayproof.classify_pairs(a, [[np.nan, 0, 0], [1, 1, 1], [2, 1, 1]])["classes"]) == ["invalid"]


def test_classify_pairs_errors_name_the_argument():
    a = np.zeros((2, 9))
    with pytest.raises(ValueError, match="^a: expected triangles"):
        rayproof.classify_pairs(np.zeros((2, 8)), a)
    with pytest.raises(ValueError, match="b"):
        rayproof.classify_pairs(a, np.zeros((3, 9)))
    with pytest.raises(ValueError, match="does not answer triangle pairs"):
        rayproof.classify_pairs(a, a, method="float")
    with pytest.raises(ValueError, match="unknown"):
        rayproof.classify_pairs(a, a, method="nope")
    with pytest.raises(ValueError, match="classify_pairs"):
        rayproof.classify("tritri", [0, 0, 0], [0, 0, 1], np.zeros(18))
