#!/usr/bin/env python3
"""VTK's vtkSelectEnclosedPoints as a containment function for `rayproof check --contains`
(docs/check.md, "Inside/outside"): the mesh goes into a vtkPolyData with double points (VTK computes
in double), and each batch of points through the filter as a user runs it, with its default
tolerance (1e-4 of the mesh's diagonal) and without its closed-surface check (rayproof judges open
meshes under the winding rule). vtkSelectEnclosedPoints answers 1 inside, 0 outside.

    rayproof check --contains 'vtk=/usr/bin/python3 examples/contains/vtk_contains.py' --mesh mesh.off

Debian: python3-vtk9."""
import os
import sys

from vtkmodules.util import numpy_support
from vtkmodules.vtkFiltersModeling import vtkSelectEnclosedPoints

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from rayproof_protocol import answer, batches, read_mesh  # noqa: E402
from vtk_mesh import polydata  # noqa: E402


def main():
    V, T = read_mesh("rayproof-contains")
    surface = polydata(V, T)
    for P in batches(3):
        select = vtkSelectEnclosedPoints()
        select.SetSurfaceData(surface)
        select.CheckSurfaceOff()
        select.SetInputData(polydata(P))
        select.Update()
        inside = numpy_support.vtk_to_numpy(select.GetOutput().GetPointData().GetArray("SelectedPoints"))
        answer("%d\n" % int(a) for a in inside)


if __name__ == "__main__":
    main()
