"""Impact pressure on SPHERIC Test 2's box: wall pressure sensors against the probes off the face (issue 28).

Runs the SPHERIC Test 2 set-up (`shoal.validation.spheric_test2`) to `--end` s with both the validation's
pressure probes (Shepard interpolation half a spacing off the box's face, `type = "points"`) and wall
pressure sensors on the face itself at P1-P4 (`type = "pressure"`, the fluid's pressure extrapolated to
the face by the linear fit and by the hydrostatic Shepard average, from the fluid in front of the face; and
the hydrostatic average without the face's normal, "sensor open", from all the fluid within 2h, which near
the box's top edge takes in the water that has run over it), every 1 ms as the experiment. A dry
probe (NaN) counts as 0. Prints, per sensor and way of measuring, against the MARIN record
(both smoothed over 10 ms as the validation does, and unsmoothed):

* the first peak's time and pressure and their errors (issue 28 asks for 0.02 s and 30 %);
* the lowest pressure in the quarter second after the measured impact, in rho0 g H0 (issue 28: not below
  -0.5);
* the ringing: the largest |p - running mean over 10 ms| after the peak's first 5 ms, over the peak.

    python benchmarks/impact_pressure.py --dp 0.05 --end 1.0 --wall adami
"""

from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np

import shoal
from shoal.options import SPHOptions
from shoal.probes import PressureSensors
from shoal.validation.spheric_test2 import BOX_HI, P_FACE, P_Y, WALLS, load_reference, spheric_test2_case
from shoal.validation.wall_impact import first_peak


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dp", type=float, default=0.05)
    ap.add_argument("--end", type=float, default=1.0)
    ap.add_argument("--wall", default=WALLS["wall_pressure"], choices=["dynamic", "adami", "mdbc"])
    ap.add_argument("--json", help="also write the figures to this JSON file")
    ap.add_argument("--options", default="{}", help="JSON object of further SPHOptions, e.g. '{\"riemann\": true}'")
    a = ap.parse_args(argv)
    extra = json.loads(a.options)
    opts = SPHOptions(**{**WALLS, "wall_pressure": a.wall, **extra})
    case = spheric_test2_case(dp=a.dp, end_time=a.end, options=opts)
    face = [[BOX_HI[0], P_Y, z] for z in P_FACE.values()]
    sensors = [PressureSensors(name=f"face_{m}", points=face, normal=[1.0, 0.0, 0.0], interval=0.001, method=m)
               for m in ("linear", "hydrostatic")]
    sensors.append(PressureSensors(name="face_open", points=face, interval=0.001))
    case = case.model_copy(update={"probes": [*case.probes, *sensors]})
    ref = load_reference()
    with tempfile.TemporaryDirectory() as tmp:
        shoal.run_case(case, Path(tmp), progress=False, plot=False)
        probes = np.loadtxt(Path(tmp) / "probe_pressure.csv", delimiter=",", skiprows=1)
        lin = np.loadtxt(Path(tmp) / "pressure_face_linear.csv", delimiter=",", skiprows=1)
        hyd = np.loadtxt(Path(tmp) / "pressure_face_hydrostatic.csv", delimiter=",", skiprows=1)
        opn = np.loadtxt(Path(tmp) / "pressure_face_open.csv", delimiter=",", skiprows=1)
    t = probes[:, 0]
    results = {"dp": a.dp, "wall": a.wall, "options": extra, "particles": case.n_particles, "end": a.end,
               "sensors": {}}
    print(f"SPHERIC Test 2, dp = {a.dp} m ({case.n_particles:,} particles), wall_pressure = {a.wall} {extra or ''}, "
          f"to {a.end} s")
    print(f"{'':4} {'measured by':16} {'peak t':>7} {'dt':>7} {'peak p':>8} {'rel':>7} | {'raw dt':>7} {'raw rel':>8}"
          f" | {'min/rho g H0':>12} {'ringing':>8}")
    for k, name in enumerate(P_FACE):
        for how, series in (("probe dp/2 off", np.nan_to_num(probes[:, 1 + 5 * k + 3])), ("sensor linear", lin[:, 1 + k]),
                            ("sensor hydro", hyd[:, 1 + k]), ("sensor open", opn[:, 1 + k])):
            m = first_peak(t, series, ref["t"], ref["pressure"][name], (0.0, min(1.0, a.end)))
            results["sensors"].setdefault(name, {})[how] = m
            s, r = m["smoothed"], m["raw"]
            print(f"{name:4} {how:16} {s['t']:7.3f} {s['dt']:+7.3f} {s['p']:8.0f} {s['rel']:+7.1%} | {r['dt']:+7.3f} "
                  f"{r['rel']:+8.1%} | {m['min_after']:12.2f} {m['ringing']:8.2f}", flush=True)
    if a.json:
        Path(a.json).write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
