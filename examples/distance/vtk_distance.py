#!/usr/bin/env python3
"""VTK's vtkImplicitPolyDataDistance as a signed distance function for `rayproof check --distance
--distance-signed` (docs/check.md, "Distances"): the mesh goes into a vtkPolyData with double points
(VTK computes in double), and each point is answered with EvaluateFunction, negative inside (VTK
takes the side from the normals at the closest point), as a user calls it. --unsigned answers its
absolute value.

    rayproof check --distance 'vtk=/usr/bin/python3 examples/distance/vtk_distance.py' --distance-signed \\
        --mesh mesh.off

Debian: python3-vtk9."""
import math
import os
import sys

from vtkmodules.vtkFiltersCore import vtkImplicitPolyDataDistance

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import answer, batches, read_mesh  # noqa: E402
from vtk_mesh import polydata  # noqa: E402


def main():
    signed = "--unsigned" not in sys.argv[1:]
    V, T = read_mesh("rayproof-distance")
    distance = vtkImplicitPolyDataDistance()
    distance.SetInput(polydata(V, T))
    for P in batches(3):
        d = (distance.EvaluateFunction(float(x), float(y), float(z)) for x, y, z in P)
        answer("%r\n" % (v if signed else math.fabs(v)) for v in d)


if __name__ == "__main__":
    main()
