#!/usr/bin/env python3
"""A whole caster for `rayproof check --caster` (docs/check.md, "Whole casters"): Möller–Trumbore
over every triangle with numpy, in float64, no BVH. It reads the mesh once, then answers each batch
of rays with one `t triangle` line per ray (`inf -1` for a miss).

    rayproof check --caster 'mt=python3 examples/caster/mt_caster.py' --mesh mesh.off

--strict tests barycentrics with > 0 instead of >= 0 (rays through edges and vertices leak);
--crash-on-nan dies with SIGSEGV on a ray with a NaN (to see how rayproof reports it)."""
import os
import signal
import sys

import numpy as np

strict = "--strict" in sys.argv
crash_on_nan = "--crash-on-nan" in sys.argv
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import answer, batches, read_mesh  # noqa: E402


def main():
    V, T = read_mesh("rayproof-caster")
    nt = len(T)
    P0, P1, P2 = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    E1, E2 = P1 - P0, P2 - P0
    for R in batches(6):
        n = len(R)
        if crash_on_nan and np.isnan(R).any():
            os.kill(os.getpid(), signal.SIGSEGV)
        O, D = R[:, :3], R[:, 3:]
        best = np.full(n, np.inf)
        tri = np.full(n, -1, dtype=np.int64)
        with np.errstate(all="ignore"):
            for start in range(0, nt, 256):  # triangles in chunks: memory n x 256
                sl = slice(start, min(nt, start + 256))
                p = np.cross(D[:, None, :], E2[None, sl, :])
                det = np.einsum("ntk,tk->nt", p, E1[sl])
                inv = 1.0 / det
                s = O[:, None, :] - P0[None, sl, :]
                u = np.einsum("ntk,ntk->nt", s, p) * inv
                q = np.cross(s, E1[None, sl, :])
                v = np.einsum("nk,ntk->nt", D, q) * inv
                t = np.einsum("tk,ntk->nt", E2[sl], q) * inv
                if strict:
                    ok = (det != 0) & (u > 0) & (v > 0) & (u + v < 1) & (t > 0)
                else:
                    ok = (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 0)
                t = np.where(ok, t, np.inf)
                k = np.argmin(t, axis=1)
                tk = t[np.arange(n), k]
                better = tk < best
                best = np.where(better, tk, best)
                tri = np.where(better, k + start, tri)
        answer("%r %d\n" % (float(a), int(b)) if np.isfinite(a) else "inf -1\n" for a, b in zip(best, tri))


if __name__ == "__main__":
    main()
