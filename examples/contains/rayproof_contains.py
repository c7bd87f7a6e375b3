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
import tempfile

ANSWER = {"outside": "0", "inside": "1", "surface": "2"}


def read_line(f):
    line = f.readline()
    if not line:
        sys.exit(0)
    return line.split()


def main():
    binary = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("RAYPROOF_BIN", "rayproof")
    f = sys.stdin
    head = read_line(f)
    if head[:2] != ["rayproof-contains", "1"]:
        sys.exit("not the rayproof contains protocol: %r" % head)
    nv = int(read_line(f)[1])
    vertices = [" ".join(read_line(f)) for _ in range(nv)]
    nt = int(read_line(f)[1])
    triangles = ["3 " + " ".join(read_line(f)) for _ in range(nt)]
    with tempfile.TemporaryDirectory() as tmp:
        mesh = os.path.join(tmp, "mesh.off")
        with open(mesh, "w") as m:
            m.write("OFF\n%d %d 0\n%s\n%s\n" % (nv, nt, "\n".join(vertices), "\n".join(triangles)))
        points_file = os.path.join(tmp, "points.txt")
        while True:
            words = read_line(f)
            if words[0] == "end":
                return
            n = int(words[1])
            points = [read_line(f) for _ in range(n)]
            valid = [all(math.isfinite(float(x)) for x in p) for p in points]
            with open(points_file, "w") as pf:
                pf.write("".join(" ".join(p) + "\n" for p, ok in zip(points, valid) if ok))
            sides = []
            if any(valid):
                run = subprocess.run([binary, "contains", mesh, points_file], capture_output=True, text=True, check=True)
                sides = run.stdout.split()
            it = iter(sides)
            sys.stdout.write("".join((ANSWER[next(it)] if ok else "0") + "\n" for ok in valid))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
