#!/usr/bin/env python3
"""A distance function for `rayproof check --distance` (docs/check.md, "Distances"): the textbook
point-triangle distance over every triangle with numpy, in float64: the distance to the plane where
the point projects inside the triangle, else the least distance to its three edges. Rounding makes
it a few ulps off, and far more near the surface (the distance to the plane is a difference of
nearly equal numbers): rayproof counts both, with reproducers.

    rayproof check --distance 'np=python3 examples/distance/numpy_distance.py' --mesh mesh.off

It reads the mesh once, then answers each batch of points with one distance per line
(`nan` for a point with a NaN or an infinity)."""
import os
import sys

import numpy as np
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import answer, batches, read_mesh  # noqa: E402


def segment_distance(P, A, B):
    """Distances from points P (n, 1, 3) to segments A-B (1, t, 3)."""
    AB = B - A
    t = np.clip(np.einsum("ntk,ntk->nt", P - A, np.broadcast_to(AB, (P.shape[0],) + AB.shape[1:])) /
                np.einsum("ntk,ntk->nt", AB, AB), 0, 1)
    return np.linalg.norm(P - (A + t[..., None] * AB), axis=2)


def main():
    V, T = read_mesh("rayproof-distance")
    nt = len(T)
    A, B, C = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    N = np.cross(B - A, C - A)
    for P in batches(3):
        n = len(P)
        best = np.full(n, np.inf)
        with np.errstate(all="ignore"):
            for start in range(0, nt, 256):  # triangles in chunks: memory n x 256
                sl = slice(start, min(nt, start + 256))
                a, b, c, nn = A[None, sl], B[None, sl], C[None, sl], N[None, sl]
                p = P[:, None, :]
                inside = ((np.einsum("ntk,ntk->nt", np.cross(b - a, p - a), nn) >= 0) &
                          (np.einsum("ntk,ntk->nt", np.cross(c - b, p - b), nn) >= 0) &
                          (np.einsum("ntk,ntk->nt", np.cross(a - c, p - c), nn) >= 0))
                plane = np.abs(np.einsum("ntk,ntk->nt", p - a, np.broadcast_to(nn, (n,) + nn.shape[1:]))) / \
                    np.linalg.norm(nn, axis=2)
                edges = np.minimum(np.minimum(segment_distance(p, a, b), segment_distance(p, b, c)),
                                   segment_distance(p, c, a))
                best = np.fmin(best, np.where(inside, plane, edges).min(axis=1))
        best[~np.isfinite(P).all(axis=1)] = np.nan
        answer("%r\n" % float(d) for d in best)


if __name__ == "__main__":
    main()
