"""Parallel VTK UnstructuredGrid (``.pvtu``): one snapshot as several ``.vtu`` pieces.

Under MPI each rank writes its own particles as a piece (`write_vtu`) and
rank 0 writes the ``.pvtu`` summary that names the pieces and the point-data
arrays they hold, so ParaView (and VTK's ``vtkXMLPUnstructuredGridReader``)
opens the snapshot as one dataset, and a ``.pvd`` can list ``.pvtu`` files
as it lists ``.vtu`` ones. `read_pvtu` (also reached through `read_vtu` for a
``.pvtu`` path) reads the pieces back, concatenated in piece order.
"""

from __future__ import annotations

import os
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from .atomic import write_text_atomic

import numpy as np

__all__ = ["pvtu_layout", "pvtu_pieces", "read_pvtu", "write_pvtu"]

# numpy dtype -> VTK XML type name (meshio's table, which writes the pieces)
_VTK_TYPES = {np.dtype(t): n for t, n in (
    (np.float32, "Float32"), (np.float64, "Float64"), (np.int8, "Int8"), (np.int16, "Int16"),
    (np.int32, "Int32"), (np.int64, "Int64"), (np.uint8, "UInt8"), (np.uint16, "UInt16"),
    (np.uint32, "UInt32"), (np.uint64, "UInt64"))}


def pvtu_layout(points, point_data):
    """The array layout a piece of `points` and `point_data` has once written by `write_vtu`.

    Parameters
    ----------
    points : array_like, shape (N, 3)
        Positions (any N, 0 included: only the dtype matters).
    point_data : dict of str to array_like
        Per-particle fields, as given to `write_vtu`.

    Returns
    -------
    dict
        ``{"points": vtk_type, "point_data": [(name, vtk_type, components or None), ...]}``
        (components None for a one-component array, as meshio writes it).
    """
    from .vtu import _prepare_point_data

    pts = np.asarray(points)
    pdt = pts.dtype if pts.dtype.kind == "f" else np.dtype(np.float64)
    n = pts.shape[0] if pts.ndim == 2 else 0
    data = _prepare_point_data(point_data, n)
    arrays = [(name, _VTK_TYPES[a.dtype], a.shape[1] if a.ndim == 2 else None) for name, a in data.items()]
    return {"points": _VTK_TYPES[np.dtype(pdt)], "point_data": arrays}


def write_pvtu(path, pieces, layout):
    """Write the ``.pvtu`` summary of a snapshot's pieces, atomically.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.pvtu`` file.
    pieces : sequence of str or os.PathLike
        The piece ``.vtu`` files, relative to the directory of `path` (an
        absolute path is made relative to it), in rank order.
    layout : dict
        `pvtu_layout` of the pieces' arrays (every piece has the same arrays).

    Returns
    -------
    Path
        `path`.
    """
    path = Path(path)
    byte_order = "LittleEndian" if sys.byteorder == "little" else "BigEndian"
    root = ET.Element("VTKFile", type="PUnstructuredGrid", version="1.0", byte_order=byte_order,
                      header_type="UInt32")
    grid = ET.SubElement(root, "PUnstructuredGrid", GhostLevel="0")
    pd = ET.SubElement(grid, "PPointData")
    for name, vtk_type, ncomp in layout["point_data"]:
        da = ET.SubElement(pd, "PDataArray", type=vtk_type, Name=name)
        if ncomp is not None:
            da.set("NumberOfComponents", str(ncomp))
    pp = ET.SubElement(grid, "PPoints")
    ET.SubElement(pp, "PDataArray", type=layout["points"], Name="Points", NumberOfComponents="3")
    for piece in pieces:
        p = Path(piece)
        if p.is_absolute():
            p = Path(os.path.relpath(p, path.parent))
        ET.SubElement(grid, "Piece", Source=p.as_posix())
    ET.indent(root)
    return write_text_atomic(path, '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n")


def pvtu_pieces(path):
    """The piece files a ``.pvtu`` names, as paths (relative ones resolved from its directory).

    Raises
    ------
    ValueError
        The file is not a PUnstructuredGrid summary.
    """
    path = Path(path)
    root = ET.parse(path).getroot()
    if root.tag != "VTKFile" or root.get("type") != "PUnstructuredGrid":
        raise ValueError(f"{path} is not a parallel VTK UnstructuredGrid (.pvtu) file")
    return [path.parent / piece.get("Source") for piece in root.iterfind("PUnstructuredGrid/Piece")]


def read_pvtu(path):
    """Read every piece of a ``.pvtu`` snapshot, concatenated in piece order.

    Parameters
    ----------
    path : str or os.PathLike
        A file written by `write_pvtu`.

    Returns
    -------
    points : numpy.ndarray, shape (N, 3)
    point_data : dict of str to numpy.ndarray
        As `read_vtu` returns them, for the union of the pieces.
    """
    from .vtu import read_vtu

    parts = [read_vtu(p) for p in pvtu_pieces(path)]
    if not parts:
        return np.empty((0, 3)), {}
    points = np.concatenate([p for p, _ in parts])
    names = parts[0][1].keys()
    return points, {k: np.concatenate([d[k] for _, d in parts]) for k in names}
