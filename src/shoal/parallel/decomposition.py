"""Slab decomposition along x: where to cut the domain between ranks.

The cuts split the particles so that each rank gets about the same weighted
count: a fluid particle weighs 1 and a boundary particle `BOUNDARY_WEIGHT`
(0.25: wall particles only visit fluid neighbours, so they cost a fraction
of a fluid particle's pair loop; `particle_weights`).

`slab_cuts` computes the cuts from every particle's x (at the start, when
every rank holds the whole set). `distributed_cuts` computes the same cuts
during a run (load balancing), when each rank holds only its own slab: the
slabs are ordered along x, so the concatenation of the ranks' sorted x is
the sorted x of the whole set, and each cut is found on the rank that holds
its weighted quantile (two reductions of a few numbers per rank; no particle
data travels). Both use `_cut_index` and `_enforce_min_width`, so for the
same particles they give the same cuts. `Slabs` holds a run's cuts and
answers which slab a point lies in.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..physics.spec import FLUID

BOUNDARY_WEIGHT = 0.25
"""Cost of a boundary particle relative to a fluid particle's in the balance of the ranks."""


def particle_weights(kinds):
    """(N,) float64 cost of each particle: 1 for fluid, `BOUNDARY_WEIGHT` for the boundaries."""
    return np.where(np.asarray(kinds) == FLUID, 1.0, BOUNDARY_WEIGHT)


class Slabs:
    """The slabs along x of the ranks of a run.

    Parameters
    ----------
    cuts : (nranks + 1,) float array
        Rank r owns the particles with cuts[r] <= x < cuts[r + 1]; cuts[0] = -inf, cuts[-1] = +inf.
    rank : int
        This process's rank.
    min_width : float
        Smallest slab width [m] a re-cut may make (the halo width; twice it on a ring of 2 ranks).
    x_period : (lo, L), optional
        A periodic x axis (the domain's low end and length [m]): the slabs close into a ring,
        rank 0's left neighbour is the last rank.
    """

    def __init__(self, cuts, rank, min_width, x_period=None):
        self.cuts = np.asarray(cuts, np.float64)
        self.rank = int(rank)
        self.size = len(self.cuts) - 1
        self.min_width = float(min_width)
        self.x_period = x_period

    @property
    def ring(self):
        """Whether x is periodic (the slabs close into a ring)."""
        return self.x_period is not None

    def bounds(self, r=None):
        """(lo, hi) [m] of rank `r`'s slab (default this rank's): the cuts, with the domain's ends
        for the outer ranks along a periodic x axis (elsewhere they are -inf / +inf)."""
        r = self.rank if r is None else r
        lo, hi = float(self.cuts[r]), float(self.cuts[r + 1])
        if self.x_period is not None:
            lo = self.x_period[0] if r == 0 else lo
            hi = self.x_period[0] + self.x_period[1] if r == self.size - 1 else hi
        return lo, hi

    def holds(self, x):
        """(len(x),) bool: which of the x [m] lie in this rank's slab (cuts[r] <= x < cuts[r + 1])."""
        x = np.asarray(x)
        return (x >= self.cuts[self.rank]) & (x < self.cuts[self.rank + 1])


def _too_many(lo, hi, nranks, min_width):
    """The InputError message when `nranks` slabs of `min_width` do not fit in lo..hi, else None."""
    max_ranks = max(int((hi - lo) // min_width), 1)
    if nranks > max_ranks:
        return (f"{nranks} MPI ranks are too many for this case: the particles span x = {lo:.4g} .. "
                f"{hi:.4g} m and each rank's slab must be at least the halo width {min_width:.4g} m wide "
                f"(2h; 4h with SPS, no-slip or Adami walls; 4h and the ghost vectors with mDBC walls; plus a "
                f"margin): use at most {max_ranks} ranks")
    return None


def _cut_index(cw, target):
    """Index i of the first particle right of the cut at cumulative weight `target`
    (``cw``: inclusive cumulative weights of the particles sorted by x): the cut
    lies between particles i - 1 and i."""
    return int(np.searchsorted(cw, target))


def _enforce_min_width(cuts, lo, hi, min_width):
    """Push the inner cuts so that every slab of lo..hi is at least `min_width` wide
    (right from the low end, then left from the high end); returns the cuts or
    None when they cannot be made that wide."""
    cuts = np.asarray(cuts, np.float64).copy()
    nranks = len(cuts) - 1
    for k in range(1, nranks):
        lo_k = lo if k == 1 else cuts[k - 1]
        cuts[k] = max(cuts[k], lo_k + min_width)
    for k in range(nranks - 1, 0, -1):
        hi_k = hi if k == nranks - 1 else cuts[k + 1]
        cuts[k] = min(cuts[k], hi_k - min_width)
    widths = np.diff(np.concatenate([[lo], cuts[1:-1], [hi]]))
    if np.any(widths < min_width * (1 - 1e-9)):
        return None
    return cuts


def slab_cuts(x, weights, nranks, min_width):
    """The nranks + 1 slab bounds along x: cuts[0] = -inf, cuts[-1] = +inf.

    Parameters
    ----------
    x : (N,) float array
        The particles' x coordinates [m].
    weights : (N,) float array
        Each particle's weight (cost), positive.
    nranks : int
        Number of slabs.
    min_width : float
        Smallest slab width allowed [m] (the halo width: a halo must come
        from the adjacent ranks only, and a particle cross at most one slab
        boundary per step).

    Returns
    -------
    (nranks + 1,) float64 array
        Rank r owns the particles with cuts[r] <= x < cuts[r + 1].

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
    msg = _too_many(lo, hi, nranks, min_width)
    if msg:
        raise InputError(msg)
    cuts = [-np.inf]
    for k in range(1, nranks):
        i = min(max(_cut_index(cw, k * total / nranks), 1), len(xs) - 1)
        cuts.append(0.5 * (xs[i - 1] + xs[i]))
    cuts.append(np.inf)
    out = _enforce_min_width(cuts, lo, hi, min_width)
    if out is None:
        raise InputError(f"cannot cut x = {lo:.4g} .. {hi:.4g} m into {nranks} slabs at least {min_width:.4g} m "
                         f"wide; use at most {max(int((hi - lo) // min_width), 1)} ranks")
    return out


def weighted_counts(comm, weight):
    """(nranks,) float64: every rank's weighted particle count (`weight`: this rank's), on every rank."""
    return np.asarray(comm.allgather(float(weight)), np.float64)


def imbalance(counts):
    """max / mean of the ranks' weighted counts (1 = perfect balance)."""
    counts = np.asarray(counts, np.float64)
    mean = counts.mean()
    return float(counts.max() / mean) if mean > 0 else 1.0


def distributed_cuts(comm, x, weights, min_width, keys=None):
    """The slab cuts of `slab_cuts` for particles spread over the ranks of `comm` by slab.

    Collective. Each rank passes its own particles, which must lie in its
    slab (rank r's x all below rank r + 1's), so that the ranks' sorted x
    concatenated in rank order is the whole set's sorted x. The result is
    the same on every rank and equals ``slab_cuts`` of the whole set (ties
    in x broken by `keys`, e.g. the particle ids, so it does not depend on
    the order of each rank's arrays).

    Parameters
    ----------
    comm : mpi4py communicator
    x : (n,) float array
        This rank's particles' x [m].
    weights : (n,) float array
        Their weights (positive).
    min_width : float
        Smallest slab width [m].
    keys : (n,) int array, optional
        Tie-break of equal x (default: the array order).

    Returns
    -------
    (nranks + 1,) float64 array or None
        The cuts, or None (on every rank) when the particles' extent cannot
        hold `nranks` slabs of `min_width` (the caller keeps its cuts).
    """
    from mpi4py import MPI

    nranks = comm.Get_size()
    x = np.asarray(x, np.float64)
    w = np.asarray(weights, np.float64)
    order = np.lexsort((np.arange(len(x)) if keys is None else np.asarray(keys), x))
    xs = x[order]
    cw = np.cumsum(w[order])
    n, wsum = len(xs), (float(cw[-1]) if len(cw) else 0.0)
    info = np.array(comm.allgather((n, wsum, float(xs[0]) if n else np.inf, float(xs[-1]) if n else -np.inf)))
    counts = info[:, 0].astype(np.int64)
    wtot = info[:, 1]
    lo, hi = float(info[:, 2].min()), float(info[:, 3].max())
    n_all = int(counts.sum())
    if n_all < 2 or _too_many(lo, hi, nranks, min_width):
        return None
    r = comm.Get_rank()
    start = int(counts[:r].sum())  # global index of this rank's first particle
    bounds = np.concatenate([[0.0], np.cumsum(wtot)])  # rank r holds the cumulative weights (bounds[r], bounds[r+1]]
    total = float(bounds[-1])
    # round 1: the global index of each cut, found on the rank holding its weighted quantile
    idx = np.full(nranks - 1, -1, np.int64)
    if n:
        for k in range(1, nranks):
            t = k * total / nranks
            if bounds[r] < t <= bounds[r + 1]:
                idx[k - 1] = start + _cut_index(cw + bounds[r], t)
    gidx = np.empty_like(idx)
    comm.Allreduce(idx, gidx, op=MPI.MAX)
    if np.any(gidx < 0):  # a quantile not found (rounding at the very end): keep the cuts
        return None
    gidx = np.clip(gidx, 1, n_all - 1)
    # round 2: the x of the particles either side of each cut, from the ranks holding them
    xv = np.full((nranks - 1, 2), -np.inf)
    for j, g in enumerate(gidx):
        for c, gi in enumerate((g - 1, g)):
            if start <= gi < start + n:
                xv[j, c] = xs[gi - start]
    gx = np.empty_like(xv)
    comm.Allreduce(xv, gx, op=MPI.MAX)
    cuts = np.concatenate([[-np.inf], 0.5 * (gx[:, 0] + gx[:, 1]), [np.inf]])
    return _enforce_min_width(cuts, lo, hi, min_width)
