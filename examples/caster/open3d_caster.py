#!/usr/bin/env python3
"""Open3D's RaycastingScene as a whole caster for `rayproof check --caster` (docs/check.md,
"Whole casters"): it reads the mesh once into a scene (float32, as Open3D stores it), then answers
each batch of rays with Open3D's cast_rays, one `t triangle` line per ray (`inf -1` for a miss).

    rayproof check --caster 'o3d=/usr/bin/python3 examples/caster/open3d_caster.py' --mesh mesh.off

Open3D runs in this child process: where it aborts (Debian's Embree asserts on a ray with a NaN,
an infinity or a zero direction), rayproof reports the crash and goes on."""
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
    if head[:2] != ["rayproof-caster", "1"]:
        sys.exit("not the rayproof caster protocol: %r" % head)
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
        R = np.array([[float(x) for x in read_line(f)] for _ in range(n)], dtype=np.float32).reshape(n, 6)
        ans = scene.cast_rays(o3d.core.Tensor(R))
        t = ans["t_hit"].numpy()
        ids = ans["primitive_ids"].numpy()
        out.write("".join("%r %d\n" % (float(a), int(b)) if np.isfinite(a) else "inf -1\n" for a, b in zip(t, ids)))
        out.flush()


if __name__ == "__main__":
    main()
