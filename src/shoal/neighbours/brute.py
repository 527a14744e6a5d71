"""Brute-force O(N^2) neighbour pairs, for tests only."""

import numpy as np


def brute_force_pairs(pos, radius, n=None):
    """All ordered pairs (i, j), i != j, with |r_i - r_j| < radius.

    Parameters
    ----------
    pos : (N, dim) array of positions [m].
    radius : float, search radius [m].
    n : int, optional, only the first n particles take part.

    Returns
    -------
    set of (i, j) tuples.
    """
    p = np.asarray(pos, dtype=np.float64)[: (len(pos) if n is None else n)]
    d2 = ((p[:, None, :] - p[None, :, :]) ** 2).sum(-1)
    i, j = np.nonzero(d2 < radius * radius)
    keep = i != j
    return set(zip(i[keep].tolist(), j[keep].tolist()))
