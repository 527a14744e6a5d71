"""Particle snapshots as VTK UnstructuredGrid files: ``.vtu`` (via meshio) and ``.pvtu``.

A ``.vtu`` holds one snapshot's particles (`write_vtu`, `read_vtu`). Under
MPI each rank writes its own particles as a ``.vtu`` piece and rank 0 the
parallel ``.pvtu`` summary that names the pieces and the point-data arrays
they hold (`write_pvtu`, `pvtu_layout`), so ParaView (and VTK's
``vtkXMLPUnstructuredGridReader``) opens the snapshot as one dataset, and a
``.pvd`` can list ``.pvtu`` files as it lists ``.vtu`` ones. `read_pvtu`
(also reached through `read_vtu` for a ``.pvtu`` path) reads the pieces
back, concatenated in piece order.
"""

from __future__ import annotations

import contextlib
import io
import os
import shutil
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np

from ..faults import reached
from .atomic import write_text_atomic

__all__ = ["pvtu_layout", "pvtu_pieces", "read_pvtu", "read_vtu", "write_pvtu", "write_vtu"]

# dtypes that VTK/ParaView readers handle awkwardly (Int8 arrays are shown as
# characters in some views, bool has no VTK type): widened to int32 on write.
_WIDEN_TO_INT32 = (np.dtype(np.bool_), np.dtype(np.int8), np.dtype(np.uint8))


def prepare_point_data(point_data, n):
    """`point_data` as written to a piece: each array checked for shape ``(n,)`` or ``(n, k)``, made
    contiguous, and awkward dtypes converted (bool and 8-bit integers to int32, float16 to float32)."""
    prepared = {}
    for name, values in point_data.items():
        arr = np.asarray(values)
        if arr.ndim not in (1, 2) or arr.shape[0] != n:
            raise ValueError(
                f"point_data[{name!r}] has shape {arr.shape}; "
                f"expected ({n},) or ({n}, k)"
            )
        if arr.dtype in _WIDEN_TO_INT32:
            arr = arr.astype(np.int32)
        elif arr.dtype == np.float16:
            arr = arr.astype(np.float32)
        elif arr.dtype.kind not in "iuf":
            raise TypeError(f"point_data[{name!r}] has unsupported dtype {arr.dtype}")
        prepared[str(name)] = np.ascontiguousarray(arr)
    return prepared


def _insert_time(src, dst, time):
    """Copy the meshio output ``src`` to ``dst`` adding a ``TimeValue`` FieldData."""
    field = (
        '<FieldData>\n<DataArray type="Float64" Name="TimeValue" '
        f'NumberOfTuples="1" format="ascii">\n{float(time)!r}\n</DataArray>\n'
        "</FieldData>\n"
    )
    with open(src, encoding="utf-8") as fin, open(dst, "w", encoding="utf-8") as fout:
        # meshio writes the opening tag on its own short line near the top.
        for line in fin:
            fout.write(line)
            if line.lstrip().startswith("<UnstructuredGrid"):
                fout.write(field)
                break
        else:
            raise RuntimeError("no <UnstructuredGrid> element in meshio output")
        shutil.copyfileobj(fin, fout)


def _fsync(path):
    """Flush a closed file's contents to disk."""
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _damaged(path, said):
    """The `InputError` for a snapshot that cannot be parsed (truncated or damaged)."""
    from ..errors import InputError

    detail = " ".join(str(said).split())[:160]
    if "Couldn't read file" in detail:  # meshio's own summary names nothing more than this message does
        detail = ""
    return InputError(f"{os.fspath(path)} is not a readable VTU snapshot (truncated or damaged"
                      + (f": {detail}" if detail else "") + "); move it aside, or write the run's snapshots again")


def _read_empty_or_none(path):
    """`_read_empty`, or None for a file that is not even well-formed XML."""
    try:
        return _read_empty(path)
    except ET.ParseError:
        return None


def _read_empty(path):
    """Return empty ``(points, point_data)`` if ``path`` has no points, else None."""
    root = ET.parse(path).getroot()
    piece = root.find("UnstructuredGrid/Piece")
    if piece is None or int(piece.get("NumberOfPoints", "-1")) != 0:
        return None

    def empty_array(da):
        dtype = np.dtype(da.get("type").lower())  # "Float64" -> float64 etc.
        ncomp = int(da.get("NumberOfComponents", "1"))
        multi = "NumberOfComponents" in da.attrib
        return np.empty((0, ncomp) if multi else (0,), dtype=dtype)

    pts_da = piece.find("Points/DataArray")
    points = empty_array(pts_da) if pts_da is not None else np.empty((0, 3))
    point_data = {
        da.get("Name"): empty_array(da) for da in piece.iterfind("PointData/DataArray")
    }
    return points, point_data


def write_vtu(path, points, point_data, time=None):
    """Write particles to a binary, zlib-compressed ``.vtu`` file atomically.

    Every particle becomes one VTK ``vertex`` cell, so ParaView renders the
    particles without a Glyph filter. The file is first written to
    ``<path>.tmp`` in the same directory and then moved over ``path`` with
    :func:`os.replace`, so a crash never leaves a half-written snapshot.

    Parameters
    ----------
    path : str or os.PathLike
        Destination file, normally ending in ``.vtu``.
    points : array_like, shape (N, 3)
        Particle positions ``(x, y, z)`` [m]. Two-dimensional runs pass
        ``y = 0``. Written as given (float32 or float64).
    point_data : dict of str to array_like
        Per-particle fields, each of shape ``(N,)`` or ``(N, k)``, for example
        ``velocity`` (N, 3) [m/s], ``density`` [kg/m^3], ``pressure`` [Pa],
        ``id`` (int32/int64) and ``kind`` (particle type). ``bool``, ``int8``
        and ``uint8`` arrays are stored as ``int32``; ``float16`` as
        ``float32``; other integer and float dtypes are kept.
    time : float, optional
        Simulation time [s]; when given it is stored as the VTK field-data
        array ``TimeValue``, which ParaView uses as the dataset time.

    Raises
    ------
    ValueError
        If ``points`` is not (N, 3) or a field's first dimension is not N.
    TypeError
        If a field has a non-numeric dtype.
    """
    path = os.fspath(path)
    pts = np.asarray(points)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"points must have shape (N, 3), got {pts.shape}")
    if pts.dtype.kind != "f":
        pts = pts.astype(np.float64)
    pts = np.ascontiguousarray(pts)
    n = pts.shape[0]
    data = prepare_point_data(point_data, n)
    cells = [("vertex", np.arange(n, dtype=np.int64).reshape(-1, 1))]
    mesh = meshio.Mesh(pts, cells, point_data=data)

    tmp = path + ".tmp"
    tmp_timed = path + ".tmp.t"
    try:
        # meshio cannot compress zero-length arrays: write empty files raw.
        compression = "zlib" if n else None
        meshio.write(
            tmp, mesh, file_format="vtu", binary=True, compression=compression
        )
        reached(f"write:{os.path.basename(path)}")  # a test hook (shoal.faults): killed mid-write
        if time is not None:
            _insert_time(tmp, tmp_timed, time)
            os.replace(tmp_timed, tmp)
        _fsync(tmp)
        os.replace(tmp, path)
    finally:
        for leftover in (tmp, tmp_timed):
            if os.path.exists(leftover):
                os.remove(leftover)


def read_vtu(path):
    """Read particles back from a ``.vtu`` file (or a ``.pvtu`` and its pieces).

    Parameters
    ----------
    path : str or os.PathLike
        File written by :func:`write_vtu` (or any point-based ``.vtu``); a
        ``.pvtu`` (`write_pvtu`, written by runs on several MPI ranks)
        is read as the union of its pieces, in piece order.

    Returns
    -------
    points : numpy.ndarray, shape (N, 3)
        Particle positions [m], in the dtype stored in the file.
    point_data : dict of str to numpy.ndarray
        Per-particle fields, shape ``(N,)`` or ``(N, k)``, with their stored
        dtypes (``int8``/``uint8``/``bool`` fields come back as ``int32``).
    """
    if os.fspath(path).endswith(".pvtu"):
        return read_pvtu(path)
    said = io.StringIO()
    try:
        # meshio prints what it could not parse and calls sys.exit(1) on a damaged file
        with contextlib.redirect_stdout(said), contextlib.redirect_stderr(said):
            mesh = meshio.read(Path(path), file_format="vtu")
    except (IndexError, ValueError):
        # meshio cannot read a mesh without points; handle that case here.
        empty = _read_empty_or_none(path)
        if empty is None:
            raise _damaged(path, said.getvalue()) from None
        return empty
    except (SystemExit, Exception) as exc:  # meshio raises assorted types (or exits) on a damaged file
        raise _damaged(path, said.getvalue() or f"{type(exc).__name__}: {exc}") from None
    point_data = {name: np.asarray(v) for name, v in mesh.point_data.items()}
    return np.asarray(mesh.points), point_data


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
    pts = np.asarray(points)
    pdt = pts.dtype if pts.dtype.kind == "f" else np.dtype(np.float64)
    n = pts.shape[0] if pts.ndim == 2 else 0
    data = prepare_point_data(point_data, n)
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
    parts = [read_vtu(p) for p in pvtu_pieces(path)]
    if not parts:
        return np.empty((0, 3)), {}
    points = np.concatenate([p for p, _ in parts])
    names = parts[0][1].keys()
    return points, {k: np.concatenate([d[k] for _, d in parts]) for k in names}
