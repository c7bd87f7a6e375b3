#!/usr/bin/env python3
"""A correct distance function for `rayproof check --distance` (docs/check.md, "Distances"): it
passes each batch of points to `rayproof distance` (exact, correctly rounded; docs/distance.md) and
answers its distances (with --signed, the signed ones; with --closest each distance with its
closest point and triangle: `d x y z triangle`). rayproof judges it with 0 findings.

    rayproof check --distance 'exact=python3 examples/distance/rayproof_distance.py build/rayproof' --mesh mesh.off

The first argument is the rayproof binary (default: $RAYPROOF_BIN, else `rayproof` on PATH). Points
are written as they were read (the protocol's numbers are exact); points with a NaN or an infinity
are answered nan here."""
import json
import math
import os
import subprocess
import sys
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import OffMesh, answer, batch_words  # noqa: E402


def main():
    args = [a for a in sys.argv[1:] if a not in ("--signed", "--closest")]
    signed = "--signed" in sys.argv
    closest = "--closest" in sys.argv
    binary = args[0] if args else os.environ.get("RAYPROOF_BIN", "rayproof")
    off = OffMesh("rayproof-distance")
    for points in batch_words():
        valid = [all(math.isfinite(float(x)) for x in p) for p in points]
        off.write_points(p for p, ok in zip(points, valid) if ok)
        lines = []
        if any(valid):
            cmd = [binary, "distance", off.mesh, off.points] + (["--signed"] if signed else [])
            run = subprocess.run(cmd + (["--json"] if closest else []), capture_output=True, text=True, check=True)
            lines = run.stdout.splitlines()
            if closest:  # one JSON object: per point its distance, side, triangle and closest point
                # (a distance beyond double's range is the string "inf" there: float() reads it)
                lines = [" ".join([repr(-float(q["distance"]) if signed and q["side"] == "inside" else float(q["distance"]))]
                                  + [repr(float(x)) for x in q["point"]] + [str(q["triangle"])])
                         for q in json.loads(run.stdout)["points"]]
        it = iter(lines)
        answer(((next(it) if closest else next(it).split()[0]) if ok else "nan") + "\n" for ok in valid)


if __name__ == "__main__":
    main()
