"""Quick-look PNG scatter plots of the particle state (no display needed)."""

from __future__ import annotations


import numpy as np

from ..physics.spec import FLUID
from .atomic import replace_file

__all__ = ["plot_particles"]


def plot_particles(
    path_png,
    points,
    values,
    kind=None,
    title="",
    value_label="",
    dim=2,
    *,
    cmap="viridis",
    vmin=None,
    vmax=None,
    dpi=150,
):
    """Save a scatter plot of the particles, fluid coloured by ``values``.

    Uses matplotlib's Agg canvas directly (no pyplot, no display), with small
    rasterized markers so that 1e5 particles plot in about a second. The PNG
    is written to ``<path_png>.tmp`` and moved into place atomically.

    Parameters
    ----------
    path_png : str or os.PathLike
        Destination PNG file.
    points : array_like, shape (N, 3)
        Particle positions ``(x, y, z)`` [m]. The plot shows x against z: the
        plane of a 2D run, or a side view of a 3D run.
    values : array_like, shape (N,)
        Scalar per particle used to colour the fluid (e.g. speed [m/s] or
        pressure [Pa]). Ignored for boundary particles.
    kind : array_like of int, shape (N,), optional
        Particle type; 0 is fluid, anything else is boundary and drawn grey.
        If None, all particles are treated as fluid.
    title : str, optional
        Axes title, e.g. ``"t = 1.25 s"``.
    value_label : str, optional
        Colorbar label, with unit, e.g. ``"|u| [m/s]"``.
    dim : {2, 3}, optional
        Spatial dimension of the run.
    cmap : str, optional
        Matplotlib colormap for the fluid.
    vmin, vmax : float, optional
        Colour range; defaults to the range of the fluid values. Fix these to
        keep a constant scale across the frames of an animation.
    dpi : int, optional
        Resolution of the PNG [dots per inch].

    Raises
    ------
    ValueError
        If ``dim`` is not 2 or 3, or array shapes do not match.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    if dim not in (2, 3):
        raise ValueError(f"dim must be 2 or 3, got {dim}")
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"points must have shape (N, 3), got {pts.shape}")
    n = pts.shape[0]
    vals = np.asarray(values, dtype=float).reshape(-1)
    if vals.shape[0] != n:
        raise ValueError(f"values has {vals.shape[0]} entries, expected {n}")
    if kind is None:
        fluid = np.ones(n, dtype=bool)
    else:
        kind = np.asarray(kind).reshape(-1)
        if kind.shape[0] != n:
            raise ValueError(f"kind has {kind.shape[0]} entries, expected {n}")
        fluid = kind == FLUID
    x, z = pts[:, 0], pts[:, 2]

    # Figure shaped roughly like the domain, within sensible limits.
    width = 8.0
    if n:
        span_x = float(np.ptp(x)) or 1.0
        span_z = float(np.ptp(z)) or 1.0
        height = float(np.clip(width * span_z / span_x, 2.5, 10.0)) + 0.8
    else:
        height = 5.0
    marker_size = float(np.clip(2.0e4 / max(n, 1), 0.2, 20.0))

    fig = Figure(figsize=(width, height), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    wall = ~fluid
    if wall.any():
        ax.scatter(x[wall], z[wall], s=marker_size, c="0.6", linewidths=0,
                   rasterized=True, label="boundary")
    if fluid.any():
        sc = ax.scatter(x[fluid], z[fluid], s=marker_size, c=vals[fluid],
                        cmap=cmap, vmin=vmin, vmax=vmax, linewidths=0,
                        rasterized=True)
        fig.colorbar(sc, ax=ax, label=value_label)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("z [m]")
    if title:
        ax.set_title(title)
    fig.tight_layout()

    replace_file(path_png, lambda tmp: fig.savefig(tmp, format="png", dpi=dpi))
