#!/usr/bin/env python3
"""Open3D's RaycastingScene.compute_occupancy as a containment function for `rayproof check
--contains` (docs/check.md, "Inside/outside"): it reads the mesh once into a scene (float32, as
Open3D stores it), then answers each batch of points with compute_occupancy (1 inside, 0 outside).

    rayproof check --contains 'o3d=/usr/bin/python3 examples/contains/open3d_contains.py' \\
        --contains-precision float --mesh mesh.off

Open3D runs in this child process: where it aborts, rayproof reports the crash and goes on."""
import os
import sys

import numpy as np
import open3d as o3d
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import answer, batches, read_mesh  # noqa: E402


def main():
    V, T = read_mesh("rayproof-contains", np.float32, np.uint32)
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.core.Tensor(V), o3d.core.Tensor(T))
    for P in batches(3, np.float32):
        occupancy = scene.compute_occupancy(o3d.core.Tensor(P)).numpy()
        answer("%d\n" % int(a) for a in occupancy)


if __name__ == "__main__":
    main()
