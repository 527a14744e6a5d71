"""Slab decomposition along x: where to cut the domain between ranks.

The cuts split the particles so that each rank gets about the same weighted
count: a fluid particle weighs 1 and a boundary particle `boundary_weight`
(0.25: wall particles only visit fluid neighbours, so they cost a fraction
of a fluid particle's pair loop). Slabs never move in this slice (load
balancing is a later one).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError


def slab_cuts(x, weights, nranks, min_width):
    """The nranks + 1 slab bounds along x: cuts[0] = -inf, cuts[-1] = +inf.

    Parameters
    ----------
    x : (N,) float array
        The particles' x coordinates [m].
    weights : (N,) float array
        Each particle's weight (cost).
    nranks : int
        Number of slabs.
    min_width : float
        Smallest slab width allowed [m] (the halo width: a halo must come
        from the adjacent ranks only, and a particle cross at most one slab
        boundary per step).

    Raises
    ------
    InputError
        More ranks than slabs of `min_width` fit in the particles' extent.
    """
    x = np.asarray(x, np.float64)
    if nranks == 1:
        return np.array([-np.inf, np.inf])
    order = np.argsort(x, kind="stable")
    xs = x[order]
    cw = np.cumsum(np.asarray(weights, np.float64)[order])
    total = cw[-1]
    lo, hi = float(xs[0]), float(xs[-1])
    max_ranks = max(int((hi - lo) // min_width), 1)
    if nranks > max_ranks:
        raise InputError(f"{nranks} MPI ranks are too many for this case: the particles span x = {lo:.4g} .. "
                         f"{hi:.4g} m and each rank's slab must be at least the halo width {min_width:.4g} m wide "
                         f"(2h, or 4h with SPS or no-slip walls, plus a margin): use at most {max_ranks} ranks")
    cuts = [-np.inf]
    for k in range(1, nranks):
        i = int(np.searchsorted(cw, k * total / nranks))
        i = min(max(i, 1), len(xs) - 1)
        cut = 0.5 * (xs[i - 1] + xs[i])
        cuts.append(cut)
    cuts.append(np.inf)
    cuts = np.asarray(cuts)
    # enforce the minimum width, pushing cuts right, then left from the top end
    for k in range(1, nranks):
        lo_k = lo if k == 1 else cuts[k - 1]
        cuts[k] = max(cuts[k], lo_k + min_width)
    for k in range(nranks - 1, 0, -1):
        hi_k = hi if k == nranks - 1 else cuts[k + 1]
        cuts[k] = min(cuts[k], hi_k - min_width)
    widths = np.diff(np.concatenate([[lo], cuts[1:-1], [hi]]))
    if np.any(widths < min_width * (1 - 1e-9)):
        raise InputError(f"cannot cut x = {lo:.4g} .. {hi:.4g} m into {nranks} slabs at least {min_width:.4g} m "
                         f"wide; use at most {max_ranks} ranks")
    return cuts
