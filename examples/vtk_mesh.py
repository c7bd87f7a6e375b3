"""Arrays into a vtkPolyData with double points (VTK computes in double), for the VTK examples
beside this file (contains/vtk_contains.py, distance/vtk_distance.py). Debian: python3-vtk9."""
import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData


def polydata(points, triangles=None):
    """Points (n, 3) and, where given, triangles (T, 3) of vertex indices."""
    pts = vtkPoints()
    pts.SetData(numpy_support.numpy_to_vtk(np.ascontiguousarray(points, dtype=np.float64), deep=True))
    poly = vtkPolyData()
    poly.SetPoints(pts)
    if triangles is not None:
        cells = vtkCellArray()
        offsets = np.arange(0, 3 * len(triangles) + 1, 3, dtype=np.int64)
        cells.SetData(numpy_support.numpy_to_vtkIdTypeArray(offsets, deep=True),
                      numpy_support.numpy_to_vtkIdTypeArray(np.asarray(triangles).reshape(-1).astype(np.int64), deep=True))
        poly.SetPolys(cells)
    return poly
