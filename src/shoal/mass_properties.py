"""Mass, centre of gravity and inertia tensor of a rigid body, from its particles or given by the user.

A body's particles sit on a lattice of spacing dp; each stands for a cube (3D) or a square (2D, the x-z
plane) of side dp and mass m_i = rho dp^dim (or the body's mass shared equally). The body's mass
properties are those of the union of these cells, exactly:

    M = sum m_i,        c = sum m_i x_i / M,

    I = sum m_i [ (r_i . r_i) E - r_i r_i^T ]  +  sum m_i (dp^2 / 12) diag(n_x, n_y, n_z),    r_i = x_i - c,

the first sum the point masses' inertia about c, the second each cell's own inertia about its centre
(parallel-axis theorem; Goldstein, Poole & Safko 2002, ch. 5): a cube of side dp has m dp^2 / 6 about each
axis through its centre; in 2D a square in x-z has m dp^2 / 6 about y and m dp^2 / 12 about x and z
(n_k = the number of the other two axes along which the cell has extent: 2, 2, 2 in 3D; 1, 2, 1 in 2D).
So a box filled with a cell-centred lattice gets the box's exact inertia, and any body gets the exact
inertia of the staircase its cells make (`tests/test_rigid_body.py`).

2D bodies are per unit width in y: M [kg/m], I [kg m^2/m]; only I_yy moves them.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class MassProperties(NamedTuple):
    """A rigid body's mass properties at t = 0 (world axes).

    Attributes
    ----------
    mass : float
        M [kg] (2D: [kg/m], per unit width).
    centre : numpy.ndarray
        c [m], the centre of gravity (3,).
    inertia : numpy.ndarray
        I [kg m^2] (2D: per unit width), the inertia tensor about c, (3, 3), symmetric:
        I_jk = sum m_i (|r_i|^2 delta_jk - r_ij r_ik) (+ the cells' own inertia, `mass_properties`).
    """

    mass: float
    centre: np.ndarray
    inertia: np.ndarray


def _cell_inertia_factors(dim):
    """diag(n_x, n_y, n_z) / 12 of the module docstring: a cell's own inertia about its centre per unit
    mass, over dp^2."""
    return np.array([2.0, 2.0, 2.0]) / 12.0 if dim == 3 else np.array([1.0, 2.0, 1.0]) / 12.0


def mass_properties(points, dp, dim, density=None, mass=None):
    """The mass properties of a body made of the particles at `points` (module docstring).

    Parameters
    ----------
    points : array_like
        (N, 3) particle positions [m] (2D: y = 0).
    dp : float
        Particle spacing [m]; each particle is a cell of volume dp^dim.
    dim : {2, 3}
    density : float, optional
        rho [kg/m^3]: m_i = rho dp^dim. Give this or `mass`.
    mass : float, optional
        The body's total mass [kg] (2D: [kg/m]), shared equally: m_i = M / N.

    Returns
    -------
    MassProperties
    """
    x = np.asarray(points, float).reshape(-1, 3)
    if dim not in (2, 3):
        raise ValueError(f"dim = {dim}: must be 2 or 3")
    if len(x) == 0:
        raise ValueError("a body of no particles has no mass; give it a shape that holds particles")
    if (density is None) == (mass is None):
        raise ValueError("give the body's density or its mass, one of the two")
    dp = float(dp)
    m_i = float(mass) / len(x) if mass is not None else float(density) * dp ** dim
    total = m_i * len(x)
    centre = x.mean(axis=0)  # equal masses: the centroid (a mean is more accurate than sum m x / M)
    if dim == 2:
        centre[1] = 0.0
    r = x - centre
    # sum m (r.r E - r r^T), formed as m (trace(S) E - S) with S = sum r r^T
    s = m_i * (r.T @ r)
    inertia = np.trace(s) * np.eye(3) - s
    inertia += np.diag(total * dp * dp * _cell_inertia_factors(dim))
    if dim == 2:
        inertia[0, 1] = inertia[1, 0] = inertia[1, 2] = inertia[2, 1] = 0.0
    return MassProperties(total, centre, 0.5 * (inertia + inertia.T))


def given_mass_properties(computed, mass=None, centre=None, inertia=None):
    """`computed` (`MassProperties`, e.g. from the particles) with the values the user gave in place of
    its own: a body that is not homogeneous (a ballasted box, a hull with its engine) has its mass, centre
    of gravity or inertia from elsewhere. `inertia` is about the centre of gravity used (the given one, or
    else the computed one), in world axes at t = 0; a 3-vector is its diagonal. Checked by
    `check_inertia`."""
    m = computed.mass if mass is None else float(mass)
    c = computed.centre if centre is None else np.asarray(centre, float).copy()
    if inertia is None:
        # the particles' inertia per unit mass, scaled to the given mass; moved to a given centre by the
        # parallel-axis theorem, I_c' = I_c + M (|d|^2 E - d d^T), d = c' - c, when the centre is given
        i = computed.inertia * (m / computed.mass)
        d = c - computed.centre
        i = i + m * (float(d @ d) * np.eye(3) - np.outer(d, d))
    else:
        i = np.asarray(inertia, float)
        i = np.diag(i) if i.shape == (3,) else i.copy()
        check_inertia(i)
    return MassProperties(m, c, i)


def check_inertia(inertia, rtol=1e-9):
    """Raise ValueError unless `inertia` ((3, 3)) can be a body's inertia tensor: symmetric (to `rtol` of
    its largest entry), positive definite, and its principal moments obey the triangle inequalities
    I_1 + I_2 >= I_3 (each moment is an integral of m (r_j^2 + r_k^2); Landau & Lifshitz 1976, sect. 32),
    equality for a flat plate (to `rtol`)."""
    i = np.asarray(inertia, float)
    if i.shape != (3, 3) or not np.all(np.isfinite(i)):
        raise ValueError("inertia must be 3 finite moments (the diagonal) or a 3 x 3 table")
    scale = float(np.max(np.abs(i)))
    if not np.all(np.abs(i - i.T) <= rtol * scale):
        raise ValueError("inertia is not symmetric (I_jk must equal I_kj)")
    moments = np.linalg.eigvalsh(0.5 * (i + i.T))
    if not moments[0] > 0:
        raise ValueError(f"inertia is not positive definite: its principal moments are "
                         f"{', '.join(f'{v:.6g}' for v in moments)}; each must be above 0")
    if moments[0] + moments[1] < moments[2] * (1.0 - rtol):
        raise ValueError(f"inertia's principal moments {', '.join(f'{v:.6g}' for v in moments)} break the "
                         "triangle inequality I1 + I2 >= I3 that every mass distribution obeys")
    return moments


def principal_axes(inertia):
    """(moments, Q): the principal moments (ascending) and a proper rotation Q (det +1) whose columns are
    the principal axes, I = Q diag(moments) Q^T."""
    moments, q = np.linalg.eigh(0.5 * (np.asarray(inertia, float) + np.asarray(inertia, float).T))
    if np.linalg.det(q) < 0:
        q[:, 2] = -q[:, 2]
    return moments, q
