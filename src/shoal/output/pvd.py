"""ParaView ``.pvd`` collection file that indexes a run's ``.vtu`` snapshots."""

from __future__ import annotations

import math
import os
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from .atomic import write_text_atomic

__all__ = ["PVDWriter"]


def read_pvd(path):
    """The snapshots a ``.pvd`` collection lists: [(time [s], file name), ...]
    in its order (the file names relative to the collection's folder).
    Raises ValueError naming what is wrong with a damaged file."""
    try:
        root = ET.parse(path).getroot()
        entries = [(float(ds.attrib["timestep"]), ds.attrib["file"]) for ds in root.iter("DataSet")]
    except (ET.ParseError, KeyError, ValueError) as exc:
        raise ValueError(f"{path}: {exc}") from exc
    if root.tag != "VTKFile" or root.get("type") != "Collection":
        raise ValueError(f"{path}: not a VTK Collection file")
    return entries


class PVDWriter:
    """Maintain ``directory/name.pvd`` listing snapshots and their times.

    The collection file is rewritten atomically (temporary file plus
    :func:`os.replace`) after every :meth:`add`, so ParaView can open it while
    the run is going and a crash keeps every entry added so far.

    Parameters
    ----------
    directory : str or os.PathLike
        Output directory; created if missing. Snapshot file names given to
        :meth:`add` are stored relative to it.
    name : str
        Base name of the collection; the file is ``directory/name.pvd``.
    resume : bool, default False
        If True and the ``.pvd`` file exists, keep its entries (for a restart).
        If False, start an empty collection, overwriting any existing file.

    Raises
    ------
    ValueError
        If ``resume`` is True and the existing file is not a readable
        collection.

    Notes
    -----
    Times are written with ``repr`` precision, so they read back exactly.
    """

    def __init__(self, directory, name, resume=False):
        self.directory = Path(directory)
        self.path = self.directory / f"{name}.pvd"
        self._entries: list[tuple[float, str]] = []
        self.directory.mkdir(parents=True, exist_ok=True)
        if resume and self.path.exists():
            self._entries = self._load(self.path)
        else:
            self._write()

    @staticmethod
    def _load(path):
        try:
            return read_pvd(path)
        except ValueError as exc:
            raise ValueError(f"cannot resume from {path}: {exc}") from exc

    def _write(self):
        byte_order = "LittleEndian" if sys.byteorder == "little" else "BigEndian"
        root = ET.Element(
            "VTKFile", type="Collection", version="0.1", byte_order=byte_order
        )
        collection = ET.SubElement(root, "Collection")
        for time, filename in self._entries:
            ET.SubElement(
                collection,
                "DataSet",
                timestep=repr(time),
                group="",
                part="0",
                file=filename,
            )
        ET.indent(root)
        write_text_atomic(self.path, '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n")

    def add(self, time, vtu_filename):
        """Append a snapshot and rewrite the collection file.

        Parameters
        ----------
        time : float
            Simulation time of the snapshot [s]; must be finite.
        vtu_filename : str or os.PathLike
            Snapshot file, relative to ``directory`` (an absolute path is made
            relative to it). Stored with forward slashes.

        Raises
        ------
        ValueError
            If ``time`` is not finite.
        """
        time = float(time)
        if not math.isfinite(time):
            raise ValueError(f"time must be finite, got {time}")
        filename = Path(vtu_filename)
        if filename.is_absolute():
            filename = Path(os.path.relpath(filename, self.directory))
        self._entries.append((time, filename.as_posix()))
        self._write()

    def truncate(self, time):
        """Drop entries later than ``time`` and rewrite the collection file.

        Use when restarting from a checkpoint at ``time`` so snapshots from the
        abandoned part of the earlier run are no longer listed.

        Parameters
        ----------
        time : float
            Last simulation time to keep [s].
        """
        self._entries = [e for e in self._entries if e[0] <= float(time)]
        self._write()

    def entries(self):
        """Return the collection's snapshots.

        Returns
        -------
        list of tuple of (float, str)
            ``(time [s], file name relative to directory)``, in file order.
        """
        return list(self._entries)
