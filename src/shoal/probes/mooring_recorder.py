"""The CSV files of a case's mooring lines during a run: a recorder per file.

For each line k of a `shoal.floating.MooringLines` named ``name`` (k numbered as in its MoorDyn file):
``<name>_line<k>.csv`` (time, fairlead tension, anchor tension [N]: the magnitudes of the line's pull on its
end points, `shoal.mooring.Mooring.line_end_forces`) and ``<name>_line<k>_nodes.csv`` (time, then the
x, y, z [m] of each node from the anchor end). One file per recorder, so that a resumed run gets each file
back as it was at the checkpoint (`shoal.probes.recorder_state`).
"""

from __future__ import annotations

import csv
from pathlib import Path

from ..mooring import TENSION_HEADER, nodes_header, nodes_row, tension_row
from .recorder_state import Recorder


class MooringLineRecorder(Recorder):
    """Appends a row to one of line `line`'s (0-based) files of `mooring` at each call (module docstring):
    its tensions, or its nodes with `nodes`."""

    def __init__(self, mooring, name, line, out_dir, nodes=False):
        self.mooring, self.line, self.nodes = mooring, line, nodes
        self.path = Path(out_dir) / f"{name}_line{line + 1}{'_nodes' if nodes else ''}.csv"
        self.file = open(self.path, "w", newline="")
        self.writer = csv.writer(self.file)
        self.writer.writerow(nodes_header(mooring, line) if nodes else TENSION_HEADER)

    def __call__(self, sim):
        row = (nodes_row if self.nodes else tension_row)(self.mooring, self.line, sim.time)
        self.writer.writerow(row)
        self.file.flush()

    def close(self):
        self.file.close()


def mooring_recorders(mooring, name, out_dir):
    """The two recorders of every line of `mooring` (tensions, then nodes), files named after `name`."""
    return [MooringLineRecorder(mooring, name, k, out_dir, nodes) for k in range(mooring.n_lines)
            for nodes in (False, True)]
