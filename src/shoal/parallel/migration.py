"""`Migration`: owned particles that left a rank's slab move to the rank whose slab they entered."""

from __future__ import annotations

import numpy as np

from ..errors import InstabilityError
from . import halo


class Migration:
    """Hands a rank's owned particles outside its slab to their new owners.

    Works on the host arrays of the model's store (``model.host_state``), with
    no ghosts held (the sort drops them first); every state array travels,
    the integrator's included.

    Parameters
    ----------
    model : DistributedModel
    link : TimedComm
    slabs : Slabs
    """

    def __init__(self, model, link, slabs):
        self.model, self.link, self.slabs = model, link, slabs

    def run(self, multi_hop=False):
        """Send the owned particles whose x left the slab to the neighbour on that side.

        Normally a particle crosses one cut at most per step (slabs are at least
        the halo width wide; farther is a blow-up, an `InstabilityError`). After a
        re-cut (`multi_hop`) a particle may be several slabs from its new owner:
        the exchange repeats, forwarding it one rank per round, until no rank holds
        a particle outside its slab (collective)."""
        m, s = self.model, self.slabs
        while True:
            r, cuts, n = s.rank, s.cuts, m.n
            x = m.store.host_of(m.pos)[:n, 0]
            lo, hi = cuts[r], cuts[r + 1]
            if s.ring:  # the shorter way round: a particle that left the domain's end was wrapped
                lo, hi = s.bounds()
                L = s.x_period[1]
                out = (x < lo) | (x >= hi)
                leftwards = out & (np.mod(lo - x, L) <= np.mod(x - hi, L))
                to_left, to_right = np.flatnonzero(leftwards), np.flatnonzero(out & ~leftwards)
            else:
                to_left = np.flatnonzero(x < lo)
                to_right = np.flatnonzero(x >= hi)
            if not multi_hop and not s.ring:
                too_far = r > 0 and np.any(x[to_left] < cuts[r - 1])
                too_far = too_far or (r + 2 < len(cuts) and np.any(x[to_right] >= cuts[r + 2]))
                if too_far:
                    raise InstabilityError(f"rank {r}: a particle crossed more than one slab in one step (slabs are "
                                           f"at least {m.halo.width:.3g} m wide): the run blew up or the time step "
                                           "is far too large")
            arrays = m.host_state()
            ncols = halo.columns(arrays)
            send_l = halo.pack(arrays, to_left)
            send_r = halo.pack(arrays, to_right)
            if len(to_left) or len(to_right):
                m.keep_rows(np.flatnonzero((x >= lo) & (x < hi)))
            from_l, from_r = self.link.shift(send_l, send_r, ncols)
            if len(from_l) + len(from_r):
                m.append_rows(np.concatenate([from_l, from_r]), ghost=0)
            if not multi_hop:
                return
            x = m.store.host_of(m.pos)[: m.n, 0]
            outside = int(np.count_nonzero(~s.holds(x)))
            if self.link.allreduce(outside, "sum") == 0:
                return
