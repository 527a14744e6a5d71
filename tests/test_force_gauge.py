"""Force gauges (`shoal.probes.ForceGauge`, `shoal.physics.forces`): the hydrodynamic force on a solid."""

import csv

import numpy as np
import pytest

import shoal
from shoal.case import Case, Fluid, FluidRegion, Output, Solid
from shoal.check import check_case
from shoal.errors import InputError
from shoal.geometry import Box, Tank
from shoal.probes import ForceGauge

RHO, G = 1000.0, 9.81
H, L = 0.3, 0.6


def _tank_case(dp, end_time=1.0, probes=()):
    """2D still water H = 0.3 m deep in a 0.6 m tank; a fixed 0.1 x 0.1 m box held in mid-water (x 0.25-0.35,
    z 0.1-0.2 m) and a vertical plate (3 dp thick, taller than the water) standing in at x = 0.5 m, water
    only on its left."""
    t = 3 * dp
    return Case(name="forces", dim=2, dp=dp, end_time=end_time, fluid=Fluid(depth=H, surface_level=H),
                solids=[Solid(name="tank", shape=Tank(lo=(0, 0, 0), hi=(L, 0, 1.5 * H))),
                        Solid(name="box", shape=Box(lo=(0.25, 0, 0.1), hi=(0.35, 0, 0.2))),
                        Solid(name="plate", shape=Box(lo=(0.5, 0, 0.0), hi=(0.5 + t, 0, 1.5 * H)))],
                fluids=[FluidRegion(shape=Box(lo=(0, 0, 0), hi=(0.5, 0, H)))], probes=list(probes),
                output=Output(interval=end_time))


@pytest.fixture(scope="module")
def settled(tmp_path_factory):
    """The tank at dp = 0.02 m run to t = 1 s (the start-up waves settle), force gauges on all three
    solids every 0.05 s: the run directory and the case."""
    out = tmp_path_factory.mktemp("forces") / "run"
    probes = [ForceGauge(name=s, solid=s, interval=0.05) for s in ("tank", "box", "plate")]
    case = _tank_case(0.02, probes=probes)
    shoal.run_case(case, out, plot=False, progress=False)
    return out, case


def _late_mean(path):
    rows = list(csv.reader(open(path)))
    assert rows[0] == ["time", "fx", "fy", "fz"]
    d = np.array([[float(v) for v in r] for r in rows[1:]])
    return d[d[:, 0] >= 0.5, 1:].mean(axis=0), d


def test_hydrostatic_forces(settled):
    """Still water after 1 s (means over t = 0.5-1 s, per metre of width):
    * Archimedes: the fixed box in mid-water (5 dp square) is pushed up by rho g V (V = 0.01 m^2) and not
      sideways, within 2 % (the hydrostatic test's pressure accuracy; measured 0.99996);
    * the plate holding the water back is pushed by rho g H^2 / 2 = 441 N/m, within 5 %: measured -3.3 %,
      and -1.7 % at dp = 0.01 m (first order in dp: within a kernel radius of the bottom corner the bed's
      particles take a share of the load);
    * all the solids together carry the water's weight, rho g x (its area), and no net horizontal force,
      within 0.2 %: the fluid's momentum balance, which the pair forces' antisymmetry makes exact at rest
      (measured 4e-6)."""
    out, case = settled
    box, _ = _late_mean(out / "force_box.csv")
    plate, _ = _late_mean(out / "force_plate.csv")
    tank, _ = _late_mean(out / "force_tank.csv")
    V = 0.1 * 0.1
    assert box[2] == pytest.approx(RHO * G * V, rel=0.02) and abs(box[0]) < 0.01 * RHO * G * V
    assert plate[0] == pytest.approx(0.5 * RHO * G * H**2, rel=0.05)
    weight = case.n_fluid * RHO * case.dp**2 * G
    total = box + plate + tank
    assert total[2] == pytest.approx(-weight, rel=0.002) and abs(total[0]) < 0.002 * weight
    assert np.all(np.array([box[1], plate[1], tank[1]]) == 0.0)  # 2D: no y


def test_force_gauge_input_is_checked():
    with pytest.raises(InputError, match="solid = 'pier' is none of the case's solids; allowed: 'tank', 'box'"):
        check_case(_tank_case(0.02, probes=[ForceGauge(name="f", solid="pier", interval=0.1)]))
    rep = _tank_case(0.02, probes=[ForceGauge(name="f", solid="box", interval=0.1)])
    rep = rep.model_copy(update={"solids": [rep.solids[0], rep.solids[1].model_copy(update={"boundary": "repulsive"}),
                                            rep.solids[2]]})
    with pytest.raises(InputError, match="repulsive"):
        check_case(rep)


def test_force_gauge_round_trips_a_case_file(tmp_path):
    case = _tank_case(0.02, probes=[ForceGauge(name="load", solid="plate", interval=0.01)])
    shoal.write_case(case, tmp_path / "c.toml")
    assert 'type = "force"' in (tmp_path / "c.toml").read_text()
    assert shoal.load_case(tmp_path / "c.toml").probes == case.probes
