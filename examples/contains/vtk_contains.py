#!/usr/bin/env python3
"""VTK's vtkSelectEnclosedPoints as a containment function for `rayproof check --contains`
(docs/check.md, "Inside/outside"): the mesh goes into a vtkPolyData with double points (VTK computes
in double), and each batch of points through the filter as a user runs it, with its default
tolerance (1e-4 of the mesh's diagonal) and without its closed-surface check (rayproof judges open
meshes under the winding rule). vtkSelectEnclosedPoints answers 1 inside, 0 outside.

    rayproof check --contains 'vtk=/usr/bin/python3 examples/contains/vtk_contains.py' --mesh mesh.off

Debian: python3-vtk9."""
import sys

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersModeling import vtkSelectEnclosedPoints


def read_line(f):
    line = f.readline()
    if not line:
        sys.exit(0)
    return line.split()


def read_rows(f, n, dtype):
    """n lines of three numbers (shortest round-trip decimals read exactly, or integers)."""
    words = " ".join(f.readline() for _ in range(n)).split()
    return np.array([float(w) for w in words] if dtype == np.float64 else [int(w) for w in words],
                    dtype=dtype).reshape(n, 3)


def polydata(points, triangles=None):
    pts = vtkPoints()
    pts.SetData(numpy_support.numpy_to_vtk(np.ascontiguousarray(points), deep=True))
    poly = vtkPolyData()
    poly.SetPoints(pts)
    if triangles is not None:
        cells = vtkCellArray()
        offsets = np.arange(0, 3 * len(triangles) + 1, 3, dtype=np.int64)
        cells.SetData(numpy_support.numpy_to_vtkIdTypeArray(offsets, deep=True),
                      numpy_support.numpy_to_vtkIdTypeArray(triangles.reshape(-1).astype(np.int64), deep=True))
        poly.SetPolys(cells)
    return poly


def main():
    f = sys.stdin
    head = read_line(f)
    if head[:2] != ["rayproof-contains", "1"]:
        sys.exit("not the rayproof contains protocol: %r" % head)
    V = read_rows(f, int(read_line(f)[1]), np.float64)
    T = read_rows(f, int(read_line(f)[1]), np.int64)
    surface = polydata(V, T)
    out = sys.stdout
    while True:
        words = read_line(f)
        if words[0] == "end":
            return
        P = read_rows(f, int(words[1]), np.float64)
        select = vtkSelectEnclosedPoints()
        select.SetSurfaceData(surface)
        select.CheckSurfaceOff()
        select.SetInputData(polydata(P))
        select.Update()
        inside = numpy_support.vtk_to_numpy(select.GetOutput().GetPointData().GetArray("SelectedPoints"))
        out.write("".join("%d\n" % int(a) for a in inside))
        out.flush()


if __name__ == "__main__":
    main()
