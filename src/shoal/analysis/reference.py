"""Reference data shipped with shoal (each file states its source)."""

from importlib import resources

import numpy as np

REFERENCES = {
    "martin_moyce_front": "damBreak_MartinMoyce1952_n2_2_a2.25in_front_table.csv",
    "koshizuka_oka_front": "damBreak_KoshizukaOka1996_front_pysph.csv",
}


def load_reference(name):
    """(T, Z) columns of a reference data set (see ``shoal/data/*.csv`` headers).

    ``martin_moyce_front``: Martin & Moyce (1952) surge front, n^2 = 2, table;
    ``koshizuka_oka_front``: Koshizuka & Oka (1996) experimental front.
    Both as Z = x/a against T = t sqrt(2 g / a).
    """
    fname = REFERENCES[name]
    text = resources.files("shoal.data").joinpath(fname).read_text()
    rows = [line.split(",") for line in text.splitlines()
            if line.strip() and not line.startswith("#") and not line[0].isalpha()]
    body = np.array(rows, dtype=float)
    return body[:, 0], body[:, 1]


def mean_relative_error(t_sim, y_sim, t_ref, y_ref, t_min=-np.inf, t_max=np.inf):
    """Mean of |y_sim(t_ref) - y_ref| / |y_ref| over t_min <= t_ref <= t_max,
    with y_sim linearly interpolated at the reference times."""
    sel = (t_ref >= t_min) & (t_ref <= t_max)
    ys = np.interp(t_ref[sel], t_sim, y_sim)
    return float(np.mean(np.abs(ys - y_ref[sel]) / np.abs(y_ref[sel])))
