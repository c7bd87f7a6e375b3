#!/usr/bin/env python3
"""Open3D's RaycastingScene distance queries as a distance function for `rayproof check --distance`
(docs/check.md, "Distances"): the mesh goes into a scene once (float32, as Open3D stores it), then
each batch of points (rounded to float32, as Open3D takes them) is answered with compute_distance,
or with compute_signed_distance under --signed (negative inside: its sign comes from the same
occupancy rays as compute_occupancy); with --closest each distance is followed by
compute_closest_points' point and primitive id (`d x y z triangle`). Open3D is float32: judge it
with --distance-precision float.

    rayproof check --distance 'o3d=/usr/bin/python3 examples/distance/open3d_distance.py' \\
        --distance-precision float --mesh mesh.off
    rayproof check --distance 'o3d=/usr/bin/python3 examples/distance/open3d_distance.py --closest' \\
        --distance-precision float --mesh mesh.off
    rayproof check --distance 'o3d=/usr/bin/python3 examples/distance/open3d_distance.py --signed' \\
        --distance-signed --distance-precision float --mesh mesh.off

Open3D runs in this child process: where it aborts, rayproof reports the crash and goes on."""
import sys

import numpy as np
import open3d as o3d


def read_line(f):
    line = f.readline()
    if not line:
        sys.exit(0)
    return line.split()


def read_rows(f, n, convert, dtype):
    words = " ".join(f.readline() for _ in range(n)).split()
    return np.array([convert(w) for w in words], dtype=dtype).reshape(n, 3)


def main():
    signed = "--signed" in sys.argv[1:]
    closest = "--closest" in sys.argv[1:]
    f = sys.stdin
    head = read_line(f)
    if head[:2] != ["rayproof-distance", "1"]:
        sys.exit("not the rayproof distance protocol: %r" % head)
    V = read_rows(f, int(read_line(f)[1]), float, np.float32)
    T = read_rows(f, int(read_line(f)[1]), int, np.uint32)
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.core.Tensor(V), o3d.core.Tensor(T))
    query = scene.compute_signed_distance if signed else scene.compute_distance
    out = sys.stdout
    while True:
        words = read_line(f)
        if words[0] == "end":
            return
        P = read_rows(f, int(words[1]), float, np.float32)
        d = query(o3d.core.Tensor(P)).numpy()
        if not closest:
            out.write("".join("%r\n" % float(x) for x in d))
        else:
            c = scene.compute_closest_points(o3d.core.Tensor(P))
            X, ids = c["points"].numpy(), c["primitive_ids"].numpy()
            out.write("".join("%r %r %r %r %d\n" % (float(x), float(q[0]), float(q[1]), float(q[2]), int(i))
                              for x, q, i in zip(d, X, ids)))
        out.flush()


if __name__ == "__main__":
    main()
