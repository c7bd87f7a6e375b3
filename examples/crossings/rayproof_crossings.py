#!/usr/bin/env python3
"""rayproof's own exact crossings as an all-hits function for `rayproof check --crossings`
(docs/check.md, "All hits"): each batch of rays goes to the Python module's Mesh.crossings (exact:
every crossing once, touches apart; docs/contains.md, "Crossings") over t > 0, and each ray's
crossings are answered as `t triangle` pairs. rayproof judges it with 0 findings.

    PYTHONPATH=build/python/module rayproof check --crossings \\
        'own=python3 examples/crossings/rayproof_crossings.py' --mesh mesh.off

The module `rayproof` must be importable (PYTHONPATH, or installed)."""
import os
import sys

import numpy as np
import rayproof
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import answer, batches, read_mesh  # noqa: E402


def main():
    V, T = read_mesh("rayproof-crossings")
    mesh = rayproof.Mesh(V, T.astype(np.uint32))
    for R in batches(6):
        r = mesh.crossings(np.ascontiguousarray(R[:, :3]), np.ascontiguousarray(R[:, 3:]), tmin=5e-324)
        t, prim, off = r["t"], r["prim"], r["offsets"]
        answer(" ".join([str(off[i + 1] - off[i])] + ["%r %d" % (float(t[k]), prim[k]) for k in range(off[i], off[i + 1])])
               + "\n" for i in range(len(R)))


if __name__ == "__main__":
    main()
