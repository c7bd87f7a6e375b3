#!/usr/bin/env python3
"""A containment function for `rayproof check --contains` (docs/check.md, "Inside/outside"): the
textbook parity test, written the naive way. For each point it casts a ray along +x and counts the
triangles whose (y, z) projection contains the point's (closed barycentric tests in float64,
numpy) with the crossing ahead: odd is inside. A ray through an edge or a vertex counts every
triangle there, and a point on the surface gets whatever the count says: rayproof finds both.

    rayproof check --contains 'parity=python3 examples/contains/parity_contains.py' --mesh mesh.off

It reads the mesh once, then answers each batch of points with one line per point: 0 outside,
1 inside. --crash-on-nan dies with SIGSEGV on a point with a NaN (to see how rayproof reports it)."""
import os
import signal
import sys

import numpy as np

crash_on_nan = "--crash-on-nan" in sys.argv
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import answer, batches, read_mesh  # noqa: E402


def main():
    V, T = read_mesh("rayproof-contains")
    nt = len(T)
    A, B, C = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]

    def orient(a, b, py, pz):  # (b - a) x (p - a) in the (y, z) plane
        return (b[..., 1] - a[..., 1]) * (pz - a[..., 2]) - (b[..., 2] - a[..., 2]) * (py - a[..., 1])

    d = orient(A, B, C[:, 1], C[:, 2])
    for P in batches(3):
        n = len(P)
        if crash_on_nan and np.isnan(P).any():
            os.kill(os.getpid(), signal.SIGSEGV)
        count = np.zeros(n, dtype=np.int64)
        with np.errstate(all="ignore"):
            for start in range(0, nt, 256):  # triangles in chunks: memory n x 256
                sl = slice(start, min(nt, start + 256))
                py, pz = P[:, 1:2], P[:, 2:3]
                u = orient(B[sl], C[sl], py, pz) / d[sl]
                v = orient(C[sl], A[sl], py, pz) / d[sl]
                w = 1 - u - v
                x = u * A[sl, 0] + v * B[sl, 0] + w * C[sl, 0]
                hit = (d[sl] != 0) & (u >= 0) & (v >= 0) & (w >= 0) & (x > P[:, 0:1])
                count += hit.sum(axis=1)
        answer("%d\n" % (c & 1) for c in count)


if __name__ == "__main__":
    main()
