"""A PNG of a case's initial geometry, to look at the case before running it.

`plot_case` draws the particles of a case coloured by type (fluid, fixed
boundary, moving boundary; optionally one colour per solid body): a side view
(x-z) and a plan view (x-y) for a 3D case, the x-z plane for a 2D case. It
uses matplotlib's Agg canvas directly (no pyplot, no display, no global
state).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .atomic import replace_file

__all__ = ["plot_case"]

FLUID, FIXED, MOVING = 0, 1, 2

_FLUID_COLOUR = "tab:blue"
_FIXED_COLOUR = "0.35"
_MOVING_COLOUR = "tab:orange"
# Qualitative colours for fixed bodies and moving bodies; blue is kept for
# the fluid, warm colours for moving bodies.
_FIXED_BODY_COLOURS = ("0.35", "tab:green", "tab:purple", "tab:brown", "tab:olive",
                       "tab:cyan", "tab:pink", "0.6", "#1b9e77", "#7570b3")
_MOVING_BODY_COLOURS = ("tab:orange", "tab:red", "#e6ab02", "#e7298a", "#a6761d")

_SEED = 12345            # subsample seed: the same case gives the same picture
_DEFAULT_MARKER = 1.5    # scatter size [points^2] when dp is not given
_MARKER_RANGE = (0.05, 20.0)

# Figure geometry [inches].
_FIG_WIDTH = 12.0
_AXES_WIDTH = _FIG_WIDTH - 1.4     # estimated room left by tick labels and axis label
_MIN_AXES_WIDTH = 4.0
_PANEL_MIN = 1.2
_PANEL_MAX = {2: 7.5, 3: 5.0}


def plot_case(path, positions, kinds, body=None, body_names=None, dim=3, title="", dp=None,
              max_points=400_000, *, dpi=150):
    """Write a PNG of a case's particles, coloured by type, before a run.

    A 3D case gets two panels sharing the x scale: a side view (x-z) with the
    fluid drawn over the boundaries, so that the water is visible through the
    side walls, and a plan view (x-y) drawn from below to above (particles
    sorted by z), so that the bed lies under the fluid. A 2D case gets one
    x-z panel. Axes have equal scales; the figure is 12 in wide and as tall
    as the extents need, within limits, so long flumes and near-square tanks
    are both readable. The legend gives the number of particles of each type
    (of the whole case, also when only a subsample is drawn).

    Parameters
    ----------
    path : str or os.PathLike
        Destination PNG file. Its folder is created if missing; the file is
        written to ``<path>.tmp`` first and moved into place.
    positions : array_like, shape (N, 3)
        Particle positions ``(x, y, z)`` [m]: x along the flume, y lateral,
        z up. A 2D case has y = 0 (y is ignored for ``dim == 2``).
    kinds : array_like of int, shape (N,)
        Particle type: 0 fluid, 1 fixed boundary, 2 moving boundary.
    body : array_like of int, shape (N,), optional
        Index of the solid body of each boundary particle, -1 for fluid. When
        given, each body gets its own colour (qualitative colours for fixed
        bodies, warm colours for moving bodies) and its own legend entry; the
        fluid is always blue.
    body_names : sequence of str, optional
        Name of each body index, used in the legend; missing names read
        ``"body <i>"``.
    dim : {2, 3}, optional
        Spatial dimension of the case.
    title : str, optional
        Figure title, e.g. the case name and resolution.
    dp : float, optional
        Particle spacing [m]. When given, markers are about one particle
        spacing wide at the figure's scale (scatter size in points^2, clipped
        to [0.05, 20]); otherwise they have a small constant size.
    max_points : int, optional
        Largest number of particles drawn. A larger case is drawn as a random
        subsample (fixed seed) of this many particles, and the title says so.
    dpi : int, optional
        Resolution of the PNG [dots per inch].

    Returns
    -------
    pathlib.Path
        The PNG written.

    Raises
    ------
    shoal.errors.InputError
        If there are no particles, the array lengths or shapes do not match,
        a kind is not 0, 1 or 2, a position is not finite, or ``dim``, ``dp``
        or ``max_points`` is out of range.

    Examples
    --------
    >>> plot_case("case.png", positions, kinds, dim=2, title="dam break, dp = 0.01 m",
    ...           dp=0.01)  # doctest: +SKIP
    PosixPath('case.png')
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.colors import to_rgba
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    pts, kinds, body, dp, max_points = _check_inputs(positions, kinds, body, dim, dp, max_points)
    n = pts.shape[0]
    groups, labels, colours, ranks = _groups(kinds, body, body_names)
    counts = np.bincount(groups, minlength=len(labels))

    idx, note = _subsample(n, max_points)
    x, y, z = (pts[idx, 0], pts[idx, 1], pts[idx, 2])
    g = groups[idx]
    rgba = np.array([to_rgba(c) for c in colours])[g]

    # Panels: (vertical coordinate, its label, panel title, drawing order).
    side_order = np.argsort(np.asarray(ranks)[g], kind="stable")
    if dim == 3:
        panels = [(z, "z [m]", "side view (x\u2013z)", side_order),
                  (y, "y [m]", "plan view (x\u2013y)", np.argsort(z, kind="stable"))]
        spans = [np.ptp(pts[:, 0]), np.ptp(pts[:, 1]), np.ptp(pts[:, 2])]
    else:
        panels = [(z, "z [m]", "", side_order)]
        spans = [np.ptp(pts[:, 0]), np.ptp(pts[:, 2])]

    # Padded data boxes of the panels, in metres.
    base = float(max(spans)) or (dp if dp else 1.0)
    pad = 0.03 * base + (0.5 * dp if dp else 0.0)
    x_lo, x_hi = float(pts[:, 0].min()) - pad, float(pts[:, 0].max()) + pad
    boxes = []
    for col in ([2, 1] if dim == 3 else [2]):
        boxes.append((float(pts[:, col].min()) - pad, float(pts[:, col].max()) + pad))
    x_range = x_hi - x_lo
    v_ranges = [hi - lo for lo, hi in boxes]

    # Figure size: 12 in wide, panel heights from the extents, within limits;
    # narrower when a panel would be taller than its limit.
    axes_width = _AXES_WIDTH
    tallest = max(v_ranges) / x_range * axes_width
    if tallest > _PANEL_MAX[dim]:
        axes_width = max(_MIN_AXES_WIDTH, axes_width * _PANEL_MAX[dim] / tallest)
    heights = [float(np.clip(axes_width * r / x_range, _PANEL_MIN, _PANEL_MAX[dim]))
               for r in v_ranges]
    shown = [i for i, c in enumerate(counts) if c > 0]
    ncols = min(len(shown), max(1, int((axes_width + 1.4) // 2.4)))
    legend_rows = math.ceil(len(shown) / ncols)
    full_title = "\n".join(t for t in (title, note) if t)
    fig_height = (sum(heights) + 0.6 * len(heights) + (0.3 * len(heights) if dim == 3 else 0.0)
                  + 0.28 * legend_rows + 0.2 + 0.3 * (full_title.count("\n") + 1 if full_title else 0))
    fig = Figure(figsize=(axes_width + 1.4, fig_height), dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(len(panels), 1, squeeze=False,
                        gridspec_kw={"height_ratios": heights})[:, 0]
    for ax, (_, vlabel, ptitle, _), (lo, hi) in zip(axes, panels, boxes):
        ax.set_xlim(x_lo, x_hi)
        ax.set_ylim(lo, hi)
        ax.set_xlabel("x [m]")
        ax.set_ylabel(vlabel)
        if ptitle:
            ax.set_title(ptitle, fontsize="medium")
    if full_title:
        fig.suptitle(full_title)
    handles = [Line2D([], [], linestyle="", marker="o", markersize=7, markeredgewidth=0,
                      color=colours[i], label=f"{labels[i]} ({counts[i]:,})") for i in shown]
    fig.legend(handles=handles, loc="outside lower center", ncols=ncols, frameon=False)

    # Lay the empty axes out, give them limits with equal x and vertical
    # scales (the same x limits for both panels), lay out again with the new
    # tick labels, then freeze the layout and set the final limits.
    scale = 1.0
    for frozen in (False, True):
        fig.canvas.draw()
        if frozen:
            fig.set_layout_engine("none")
        sizes = [ax.get_position().size * fig.get_size_inches() for ax in axes]
        scale = min(min(w / x_range, h / r) for (w, h), r in zip(sizes, v_ranges))  # in per m
        xc = 0.5 * (x_lo + x_hi)
        for ax, (w, h), (lo, hi) in zip(axes, sizes, boxes):
            vc = 0.5 * (lo + hi)
            ax.set_xlim(xc - 0.5 * w / scale, xc + 0.5 * w / scale)
            ax.set_ylim(vc - 0.5 * h / scale, vc + 0.5 * h / scale)
            if frozen:  # the limits already fit the box: this only records it
                ax.set_aspect("equal", adjustable="box")

    if dp:
        marker = float(np.clip((dp * scale * 72.0) ** 2, *_MARKER_RANGE))
    else:
        marker = _DEFAULT_MARKER
    for ax, (v, _, _, order) in zip(axes, panels):
        ax.scatter(x[order], v[order], s=marker, c=rgba[order], linewidths=0, marker="o",
                   rasterized=True)

    return replace_file(path, lambda tmp: fig.savefig(tmp, format="png", dpi=dpi))


def _check_inputs(positions, kinds, body, dim, dp, max_points):
    """Validate and convert the inputs of `plot_case`; raise InputError."""
    if dim not in (2, 3):
        raise InputError(f"dim = {dim!r}; allowed 2 or 3")
    pts = np.asarray(positions, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise InputError(f"positions must be an (N, 3) array of x, y, z in metres, got shape {pts.shape}")
    n = pts.shape[0]
    if n == 0:
        raise InputError("the case has no particles to plot")
    if not np.isfinite(pts).all():
        raise InputError(f"{int((~np.isfinite(pts)).any(axis=1).sum())} particle positions are NaN or infinite")
    kinds = np.asarray(kinds).reshape(-1)
    if kinds.shape[0] != n:
        raise InputError(f"kinds has {kinds.shape[0]} entries but there are {n} positions")
    if not np.isin(kinds, (FLUID, FIXED, MOVING)).all():
        bad = np.unique(kinds[~np.isin(kinds, (FLUID, FIXED, MOVING))])[:5]
        raise InputError(f"unknown particle kinds {bad.tolist()}; allowed 0 (fluid), 1 (fixed boundary), "
                         "2 (moving boundary)")
    kinds = kinds.astype(np.int64)
    if body is not None:
        body = np.asarray(body).reshape(-1)
        if body.shape[0] != n:
            raise InputError(f"body has {body.shape[0]} entries but there are {n} positions")
        if body.size and not np.issubdtype(body.dtype, np.integer):
            raise InputError(f"body must hold integer body indices (-1 for fluid), got dtype {body.dtype}")
        body = body.astype(np.int64)
    if dp is not None:
        try:
            dp = float(dp)
        except (TypeError, ValueError):
            raise InputError(f"dp = {dp!r} m must be a positive number of metres") from None
        if not (math.isfinite(dp) and dp > 0.0):
            raise InputError(f"dp = {dp!r} m must be a positive number of metres")
    if isinstance(max_points, bool) or not isinstance(max_points, (int, np.integer)) or max_points < 1:
        raise InputError(f"max_points = {max_points!r}; must be a positive integer")
    return pts, kinds, body, dp, int(max_points)


def _groups(kinds, body, body_names):
    """Colour groups of the particles.

    Returns the group index of each particle and, per group, its legend
    label, colour and side-view drawing rank (fixed 0, moving 1, fluid 2:
    higher is drawn later).
    """
    groups = np.zeros(kinds.shape[0], dtype=np.int64)
    labels, colours, ranks = ["fluid"], [_FLUID_COLOUR], [2]
    if body is None:
        labels += ["fixed boundary", "moving boundary"]
        colours += [_FIXED_COLOUR, _MOVING_COLOUR]
        ranks += [0, 1]
        groups[kinds == FIXED] = 1
        groups[kinds == MOVING] = 2
        return groups, labels, colours, ranks
    names = list(body_names) if body_names is not None else []
    for kind, palette, rank, suffix, default in (
            (FIXED, _FIXED_BODY_COLOURS, 0, "", "fixed boundary"),
            (MOVING, _MOVING_BODY_COLOURS, 1, " (moving)", "moving boundary")):
        mask = kinds == kind
        for j, b in enumerate(np.unique(body[mask])):
            if b < 0:
                label, colour = default, _FIXED_COLOUR if kind == FIXED else _MOVING_COLOUR
            else:
                name = str(names[b]) if b < len(names) else f"body {b}"
                label, colour = name + suffix, palette[j % len(palette)]
            groups[mask & (body == b)] = len(labels)
            labels.append(label)
            colours.append(colour)
            ranks.append(rank)
    return groups, labels, colours, ranks


def _subsample(n, max_points):
    """Indices of the particles drawn (sorted) and a note for the title.

    All particles when ``n <= max_points`` (and an empty note); otherwise a
    random subsample of ``max_points`` without repetition, with a fixed seed.
    """
    if n <= max_points:
        return np.arange(n), ""
    rng = np.random.default_rng(_SEED)
    idx = np.sort(rng.choice(n, size=max_points, replace=False))
    return idx, f"subsample of {max_points:,} of {n:,} particles shown"
