"""Shared helpers for the rayproof module's tests: the command-line tool, the data directory, case files."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import rayproof

HERE = pathlib.Path(__file__).resolve().parent
DATA = pathlib.Path(os.environ.get("RAYPROOF_DATA_DIR", HERE.parents[1] / "data"))
BIN = os.environ.get("RAYPROOF_BIN", str(HERE.parents[1] / "build" / "rayproof"))


def run_cli(*args, status=0):
    """Runs the rayproof command-line tool, expecting exit `status`; returns its standard output lines."""
    out = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True)
    assert out.returncode == status, out.stderr[-2000:]
    return out.stdout.splitlines()


def number(tok):
    """A case-file number as strtod reads it (decimal, C99 hex float, inf, nan)."""
    try:
        return float(tok)
    except ValueError:
        return float.fromhex(tok)


def read_cases(path):
    """The cases of a case file as (kind, values) in file order."""
    cases = []
    for line in pathlib.Path(path).read_text().splitlines():
        fields = line.split("#", 1)[0].split()
        if fields:
            cases.append((fields[0], [number(t) for t in fields[1:]]))
    return cases


def parse_result(line):
    """`CLASS T T2` -> (class, t, t2) with NaN for '-'."""
    c, t, t2 = line.split()
    return c, (np.nan if t == "-" else float(t)), (np.nan if t2 == "-" else float(t2))


def same_float(a, b):
    """Equal doubles (bit for bit, -0.0 apart from 0.0), or both NaN."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return (np.isnan(a) & np.isnan(b)) | (a.view(np.int64) == b.view(np.int64))


@pytest.fixture(scope="session")
def sample():
    return read_cases(DATA / "sample.txt")


def classify_cases(cases, method):
    """Every case through rayproof.classify, one call per kind; results in case order (None, NaN for
    the kinds the method does not answer)."""
    classes = [None] * len(cases)
    t = np.full(len(cases), np.nan)
    t2 = np.full(len(cases), np.nan)
    kinds = next(m["kinds"] for m in rayproof.methods() if m["name"] == method)
    for kind in {k for k, _ in cases} & set(kinds):
        idx = [i for i, (k, _) in enumerate(cases) if k == kind]
        v = np.array([cases[i][1] for i in idx])
        r = rayproof.classify(kind, v[:, 0:3], v[:, 3:6], v[:, 6:], method=method)
        for j, i in enumerate(idx):
            classes[i] = str(r["classes"][j])
        t[idx] = r["t"]
        t2[idx] = r["t2"]
    return classes, t, t2
