#!/usr/bin/env python3
"""An all-hits function for `rayproof check --crossings` (docs/check.md, "All hits"): Möller–Trumbore
over every triangle with numpy, in float64, no BVH, every hit at t > 0 kept, sorted by t. A ray
through an edge shared by two triangles is usually reported by both (a duplicate) or, rounding the
other way, by neither (a missing crossing); a ray grazing a silhouette is reported as a crossing
(a touch): rayproof counts each, with one-line reproducers.

    rayproof check --crossings 'np=python3 examples/crossings/numpy_crossings.py' --mesh mesh.off

It reads the mesh once, then answers each batch of rays with one line per ray: the number of hits,
then `t triangle` per hit (`0` for a ray with a NaN or an infinity: every test fails on NaN)."""
import os
import sys

import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import answer, batches, read_mesh  # noqa: E402


def main():
    V, T = read_mesh("rayproof-crossings")
    P0, E1, E2 = V[T[:, 0]], V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]
    for R in batches(6):
        lines = []
        with np.errstate(all="ignore"):
            for o, d in zip(R[:, :3], R[:, 3:]):
                p = np.cross(d[None, :], E2)
                det = np.einsum("tk,tk->t", E1, p)
                s = o[None, :] - P0
                q = np.cross(s, E1)
                u = np.einsum("tk,tk->t", s, p) / det
                v = (q @ d) / det
                t = np.einsum("tk,tk->t", E2, q) / det
                hit = np.nonzero((det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0) & np.isfinite(t))[0]
                hit = hit[np.argsort(t[hit], kind="stable")]
                lines.append(" ".join([str(len(hit))] + ["%r %d" % (float(t[k]), k) for k in hit]) + "\n")
        answer(lines)


if __name__ == "__main__":
    main()
