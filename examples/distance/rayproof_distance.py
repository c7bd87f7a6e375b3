#!/usr/bin/env python3
"""A correct distance function for `rayproof check --distance` (docs/check.md, "Distances"): it
passes each batch of points to `rayproof distance` (exact, correctly rounded; docs/distance.md) and
answers its distances (with --signed, the signed ones). rayproof judges it with 0 findings.

    rayproof check --distance 'exact=python3 examples/distance/rayproof_distance.py build/rayproof' --mesh mesh.off

The first argument is the rayproof binary (default: $RAYPROOF_BIN, else `rayproof` on PATH). Points
are written as they were read (the protocol's numbers are exact); points with a NaN or an infinity
are answered nan here."""
import math
import os
import subprocess
import sys
import tempfile



def read_line(f):
    line = f.readline()
    if not line:
        sys.exit(0)
    return line.split()


def main():
    args = [a for a in sys.argv[1:] if a != "--signed"]
    signed = "--signed" in sys.argv
    binary = args[0] if args else os.environ.get("RAYPROOF_BIN", "rayproof")
    f = sys.stdin
    head = read_line(f)
    if head[:2] != ["rayproof-distance", "1"]:
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
            lines = []
            if any(valid):
                cmd = [binary, "distance", mesh, points_file] + (["--signed"] if signed else [])
                run = subprocess.run(cmd, capture_output=True, text=True, check=True)
                lines = run.stdout.splitlines()
            it = iter(lines)
            sys.stdout.write("".join((next(it).split()[0] if ok else "nan") + "\n" for ok in valid))
            sys.stdout.flush()


if __name__ == "__main__":
    main()
