"""`ParticleStore`: the rows of a model's per-particle arrays, their capacity and growth.

Every per-particle array of a model (state, rates, work arrays, the
integrator's) holds `capacity` rows, of which the first ``model.n`` are
active particles. When more rows are needed (an MPI rank receives migrating
particles or a larger halo; an inflow boundary creates particles) `ensure`
grows them all together, in one place:

- NumPy arrays (a backend working in host memory) are resized in place, so
  every reference to them stays valid;
- device arrays cannot be: new ones are allocated, the active rows copied
  on the device, and every reference to an old array re-pointed to its
  successor: attributes of the model and of its array owners (the
  integrator, registered by ``Model.new_array(..., owner=)``), and items of
  their lists and dicts of arrays (``scratch``, ``extra_arrays``).

The neighbour grid's per-particle work arrays follow. Arrays indexed by
particle id (the motions' start positions, the wall normals) are not
per-particle rows and keep their size.

Host mirrors. Code that edits particle rows with NumPy (the MPI bookkeeping
of a sort: dropping ghosts, migration, a new halo) reads `host_of` (a): `a`
itself on a backend whose arrays live in host memory, else a host copy that
`to_host` and `to_device` keep in step with the device.
"""

from __future__ import annotations

import numpy as np


class ParticleStore:
    """Capacity, growth and host mirrors of one model's per-particle arrays.

    Parameters
    ----------
    model : Model
        The model whose arrays are stored; `per_particle_arrays` lists them,
        ``array_owners`` the other objects that hold some of them.
    capacity : int
        Rows each per-particle array holds now.
    """

    def __init__(self, model, capacity):
        self.model = model
        self.backend = model.backend
        self.capacity = int(capacity)
        self.resizes = 0
        """Times the arrays were given another size (`resize`)."""
        self._mirrors = {}  # id(array) -> (array, host copy); the tuple holds the array, so its id stays unique

    # --------------------------------------------------------------- mirrors
    def mirror(self, arrays):
        """Give each of `arrays` a host copy (`host_of`) when the backend's arrays are not in host memory."""
        if self.backend.host_memory:
            return
        for a in arrays:
            if id(a) not in self._mirrors:
                self._mirrors[id(a)] = (a, np.zeros(a.shape, a.dtype))

    def host_of(self, a):
        """The NumPy array that stands for the particle array `a` in host code: `a` itself in host
        memory, else its host copy (valid after `to_host`)."""
        entry = self._mirrors.get(id(a))
        return a if entry is None else entry[1]

    def to_host(self, arrays, n):
        """Copy rows 0..n of `arrays` to their host copies (nothing in host memory)."""
        if self._mirrors:
            for a in arrays:
                self.backend.copy_to_host(self.host_of(a), a, n)

    def to_device(self, arrays, n):
        """Copy rows 0..n of `arrays` from their host copies back (nothing in host memory)."""
        if self._mirrors:
            for a in arrays:
                self.backend.copy_into(a, self.host_of(a), n)

    # ---------------------------------------------------------------- growth
    def ensure(self, rows, spare=0, limit=None):
        """Grow the arrays when `rows` do not fit: to 1.25 `rows` + `spare`, at most
        max(`limit`, `rows`) (the whole case's particles, say)."""
        if rows <= self.capacity:
            return
        want = int(1.25 * rows) + int(spare)
        self.resize(want if limit is None else min(want, max(int(limit), rows)))

    def resize(self, capacity):
        """Give every per-particle array `capacity` rows, keeping the active rows 0..n."""
        capacity = max(int(capacity), 1)
        if capacity == self.capacity:
            return
        m = self.model
        if self.backend.host_memory:
            seen = set()
            for a in m.per_particle_arrays():
                if id(a) not in seen:
                    seen.add(id(a))
                    a.resize((capacity,) + a.shape[1:], refcheck=False)
        else:
            self._reallocate(capacity)
        m.grid.resize(capacity)
        self.capacity = capacity
        self.resizes += 1

    def _reallocate(self, capacity):
        b, m = self.backend, self.model
        keep = min(m.n, capacity)
        old = m.per_particle_arrays()
        new = {}
        for a in old:
            if id(a) not in new:
                c = b.zeros((capacity,) + tuple(a.shape[1:]), a.dtype)
                b.copy_into(c, a, keep)
                new[id(a)] = c
        for obj in [m, *m.array_owners]:
            for name, value in list(vars(obj).items()):
                if id(value) in new:
                    setattr(obj, name, new[id(value)])
                elif isinstance(value, list):
                    value[:] = [new.get(id(v), v) for v in value]
                elif isinstance(value, dict) and value is not self._mirrors:
                    for key, v in list(value.items()):
                        value[key] = new.get(id(v), v)
        mirrors = {}
        for a, host in self._mirrors.values():
            host.resize((capacity,) + host.shape[1:], refcheck=False)
            c = new.get(id(a), a)
            mirrors[id(c)] = (c, host)
        self._mirrors = mirrors
        del old  # the old arrays lived until here, so no id above was reused
