"""`Rebalancer`: moves the slab cuts when the ranks' loads drift apart, and its settings.

Every `interval` steps (at the sort) the ranks compare their weighted counts
(`shoal.parallel.decomposition.particle_weights`); when max / mean exceeds
`threshold`, the cuts move to the weighted quantiles of the particles'
current x (`distributed_cuts`: a few numbers per rank travel, no particles)
and the particles migrate to their new owners (several hops if a cut moved
past a neighbour's slab) before the fresh halo is fetched. The physics is
unchanged: a particle's rates do not depend on which rank owns it.
"""

from __future__ import annotations

import math
import os

import numpy as np

from ..errors import InputError
from .decomposition import distributed_cuts, imbalance, particle_weights, weighted_counts

REBALANCE_INTERVAL = 20
REBALANCE_THRESHOLD = 1.1


def _from_env(env, name, parse, default, allowed):
    """`parse` of the variable `name` of `env` (`default` when unset or blank), or an InputError."""
    text = env.get(name, "").strip()
    try:
        return parse(text) if text else default
    except ValueError:
        raise InputError(f"{name} = {text!r}: {allowed}") from None


def rebalance_settings(interval=None, threshold=None, environ=None):
    """(interval, threshold) of the load balancing: the arguments, else the
    environment (``SHOAL_MPI_REBALANCE_INTERVAL``, ``SHOAL_MPI_REBALANCE_THRESHOLD``),
    else the defaults (20 steps, 1.1).

    Parameters
    ----------
    interval : int, optional
        Steps between balance checks; 0 turns load balancing off.
    threshold : float, optional
        Re-cut when the ranks' max / mean weighted count exceeds it (>= 1).
    environ : mapping, optional
        Where to read the variables (default: ``os.environ``).

    Raises
    ------
    InputError
        A value that is not an integer >= 0 / a number >= 1.
    """
    env = os.environ if environ is None else environ
    if interval is None:
        interval = _from_env(env, "SHOAL_MPI_REBALANCE_INTERVAL", int, REBALANCE_INTERVAL,
                             "give a whole number of steps >= 0 (0: no load balancing)")
    if threshold is None:
        threshold = _from_env(env, "SHOAL_MPI_REBALANCE_THRESHOLD", float, REBALANCE_THRESHOLD,
                              "give a number >= 1 (the max / mean weighted particle count that triggers a re-cut)")
    if isinstance(interval, bool) or int(interval) != interval or interval < 0:
        raise InputError(f"rebalance interval {interval!r}: give a whole number of steps >= 0 (0: no load balancing)")
    if not (math.isfinite(float(threshold)) and float(threshold) >= 1.0):
        raise InputError(f"rebalance threshold {threshold!r}: give a number >= 1 (max / mean weighted particle count)")
    return int(interval), float(threshold)


class Rebalancer:
    """The load balancing of a distributed model.

    Parameters
    ----------
    model : DistributedModel
    link : TimedComm
    slabs : Slabs
        The cuts it moves.
    migration : Migration
        Moves the particles to their new owners.
    interval, threshold : optional
        See `rebalance_settings`.
    """

    def __init__(self, model, link, slabs, migration, interval=None, threshold=None):
        self.model, self.link, self.slabs, self.migration = model, link, slabs, migration
        self.interval, self.threshold = rebalance_settings(interval, threshold)
        self.records = []
        """One dict per re-cut (see `rebalance`)."""

    def due(self, sort_count):
        """Whether the sort numbered `sort_count` (1: before step 1) checks the balance: the start
        of every `interval`-th step after the first."""
        k = sort_count - 1
        return self.interval > 0 and k > 0 and k % self.interval == 0

    def weighted_count(self):
        """This rank's owned active particles weighted by cost (`particle_weights`)."""
        m = self.model
        return float(particle_weights(m.store.host_of(m.kind)[: m.n][m.owned]).sum())

    def rebalance(self, force=False):
        """Collective: when the ranks' max / mean weighted count exceeds
        `threshold` (or `force`), move the cuts to the weighted quantiles of
        the particles' current x and migrate the particles to their new owners.
        Call with no ghosts held (the model's sort does, between dropping the
        ghosts and fetching the new halo, on the host arrays).

        Returns
        -------
        dict or None
            The record appended to `records` (``sort``: the sort count,
            ``time`` [s], ``imbalance_before`` / ``imbalance_after`` (max /
            mean weighted count), ``weighted_before`` / ``weighted_after``
            and ``counts_before`` / ``counts_after`` (particles per rank),
            ``cuts`` (the new inner cuts [m])), or None when no re-cut was made
            (balanced within the threshold, the cuts already where they would
            go, or no room for slabs one halo wide).
        """
        m, s, link = self.model, self.slabs, self.link
        own = m.owned
        before = link.timed(weighted_counts, link.comm, self.weighted_count())
        ratio = imbalance(before)
        if not force and ratio <= self.threshold:
            return None
        w = particle_weights(m.store.host_of(m.kind)[: m.n][own])
        cuts = link.timed(distributed_cuts, link.comm, m.store.host_of(m.pos)[: m.n, 0][own], w, s.min_width,
                          keys=m.store.host_of(m.idp)[: m.n][own])
        if cuts is None or np.array_equal(cuts, s.cuts):  # no room to move, or already the best cut
            return None
        counts_before = link.allgather(int(np.count_nonzero(own)))
        s.cuts = cuts
        self.migration.run(multi_hop=True)
        after = link.timed(weighted_counts, link.comm, self.weighted_count())
        rec = {"sort": m.sort_count, "time": float(m.time), "imbalance_before": ratio,
               "imbalance_after": imbalance(after), "weighted_before": before.tolist(),
               "weighted_after": after.tolist(), "counts_before": counts_before,
               "counts_after": link.allgather(int(m.n)), "cuts": cuts[1:-1].tolist()}
        self.records.append(rec)
        return rec
