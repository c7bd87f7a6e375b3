#!/usr/bin/env python3
"""A correct containment function for `rayproof check --contains` (docs/check.md, "Inside/outside"):
it passes each batch of points to `rayproof contains` (exact; docs/contains.md) and answers 0
outside, 1 inside, 2 on the surface. rayproof judges it with 0 findings.

    rayproof check --contains 'exact=python3 examples/contains/rayproof_contains.py build/rayproof' --mesh mesh.off

The argument is the rayproof binary (default: $RAYPROOF_BIN, else `rayproof` on PATH). Points are
written as they were read (the protocol's numbers are exact), so `rayproof contains` sees the same
doubles; points with a NaN or an infinity have no side and are answered 0 here."""
import math
import os
import subprocess
import sys

ANSWER = {"outside": "0", "inside": "1", "surface": "2"}
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import OffMesh, answer, batch_words  # noqa: E402


def main():
    binary = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("RAYPROOF_BIN", "rayproof")
    off = OffMesh("rayproof-contains")
    for points in batch_words():
        valid = [all(math.isfinite(float(x)) for x in p) for p in points]
        off.write_points(p for p, ok in zip(points, valid) if ok)
        sides = []
        if any(valid):
            run = subprocess.run([binary, "contains", off.mesh, off.points], capture_output=True, text=True, check=True)
            sides = run.stdout.split()
        it = iter(sides)
        answer((ANSWER[next(it)] if ok else "0") + "\n" for ok in valid)


if __name__ == "__main__":
    main()
