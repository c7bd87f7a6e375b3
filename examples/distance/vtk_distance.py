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
import sys

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersCore import vtkImplicitPolyDataDistance


def read_line(f):
    line = f.readline()
    if not line:
        sys.exit(0)
    return line.split()


def read_rows(f, n, convert):
    return [[convert(w) for w in f.readline().split()] for _ in range(n)]


def main():
    signed = "--unsigned" not in sys.argv[1:]
    f = sys.stdin
    head = read_line(f)
    if head[:2] != ["rayproof-distance", "1"]:
        sys.exit("not the rayproof distance protocol: %r" % head)
    V = np.array(read_rows(f, int(read_line(f)[1]), float), dtype=np.float64).reshape(-1, 3)
    T = np.array(read_rows(f, int(read_line(f)[1]), int), dtype=np.int64).reshape(-1, 3)
    points = vtkPoints()
    points.SetData(numpy_support.numpy_to_vtk(V, deep=True))
    cells = vtkCellArray()
    cells.SetData(numpy_support.numpy_to_vtkIdTypeArray(np.arange(0, 3 * len(T) + 1, 3, dtype=np.int64), deep=True),
                  numpy_support.numpy_to_vtkIdTypeArray(T.reshape(-1).copy(), deep=True))
    surface = vtkPolyData()
    surface.SetPoints(points)
    surface.SetPolys(cells)
    distance = vtkImplicitPolyDataDistance()
    distance.SetInput(surface)
    out = sys.stdout
    while True:
        words = read_line(f)
        if words[0] == "end":
            return
        answers = []
        for x, y, z in read_rows(f, int(words[1]), float):
            d = distance.EvaluateFunction(x, y, z)
            answers.append("%r\n" % (d if signed else math.fabs(d)))
        out.write("".join(answers))
        out.flush()


if __name__ == "__main__":
    main()
