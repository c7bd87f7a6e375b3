#!/usr/bin/env python3
"""Open3D's RaycastingScene.compute_occupancy as a containment function for `rayproof check
--contains` (docs/check.md, "Inside/outside"): it reads the mesh once into a scene (float32, as
Open3D stores it), then answers each batch of points with compute_occupancy (1 inside, 0 outside).

    rayproof check --contains 'o3d=/usr/bin/python3 examples/contains/open3d_contains.py' \\
        --contains-precision float --mesh mesh.off

Open3D runs in this child process: where it aborts, rayproof reports the crash and goes on."""
import sys

import numpy as np
import open3d as o3d


def read_line(f):
    line = f.readline()
    if not line:
        sys.exit(0)
    return line.split()


def main():
    f = sys.stdin
    head = read_line(f)
    if head[:2] != ["rayproof-contains", "1"]:
        sys.exit("not the rayproof contains protocol: %r" % head)
    nv = int(read_line(f)[1])
    V = np.array([[float(x) for x in read_line(f)] for _ in range(nv)], dtype=np.float32).reshape(nv, 3)
    nt = int(read_line(f)[1])
    T = np.array([[int(x) for x in read_line(f)] for _ in range(nt)], dtype=np.uint32).reshape(nt, 3)
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.core.Tensor(V), o3d.core.Tensor(T))
    out = sys.stdout
    while True:
        words = read_line(f)
        if words[0] == "end":
            return
        n = int(words[1])
        P = np.array([[float(x) for x in read_line(f)] for _ in range(n)], dtype=np.float32).reshape(n, 3)
        occupancy = scene.compute_occupancy(o3d.core.Tensor(P)).numpy()
        out.write("".join("%d\n" % int(a) for a in occupancy))
        out.flush()


if __name__ == "__main__":
    main()
