"""The validation cases `shoal validate` knows, by name, in report order."""

from __future__ import annotations

from ..errors import InputError
from .active_absorption import ActiveAbsorptionCase
from .archimedes import Archimedes
from .bores import TidalBores, UndularAmplitude
from .bridge_piers import BridgePiers
from .dam_break import DamBreak2D
from .flap import FlapWaves
from .floating_waves import FloatingBoxWaves
from .focused_wave import FocusedWave
from .heave_decay import HeaveDecay
from .hydrostatic import Hydrostatic
from .periodic_runup import PeriodicRunup
from .poiseuille import Poiseuille
from .resolution import ResolutionStudy
from .rip_current import RipCurrent
from .roll_decay import RollDecay
from .ship_section_decay import ShipSectionDecay
from .ship_section_waves import ShipSectionWaves
from .sluice_gate import SluiceGate
from .weir import BroadCrestedWeir
from .spheric_test2 import SphericTest2
from .wall_impact import WallImpact
from .wave_flume import WaveFlume


def all_cases():
    """A fresh instance of every validation case, in report order."""
    return [
        Hydrostatic(),
        Poiseuille(),
        DamBreak2D(),
        TidalBores(),
        UndularAmplitude(),
        ResolutionStudy(),
        RipCurrent(),
        SphericTest2(),
        WallImpact(),
        WaveFlume(),
        PeriodicRunup(),
        FocusedWave(),
        BridgePiers(),
        ActiveAbsorptionCase(),
        FlapWaves(),
        HeaveDecay(),
        RollDecay(),
        ShipSectionDecay(),
        FloatingBoxWaves(),
        ShipSectionWaves(),
        Archimedes(),
        SluiceGate(),
        BroadCrestedWeir(),
    ]


VALIDATION_CASES = {c.name: c for c in all_cases()}
"""The validation cases by name, in report order."""


def get_cases(names=None):
    """The validation cases named (all of them, in report order, when `names` is empty).

    Raises
    ------
    InputError
        An unknown name (the message lists the known ones).
    """
    if not names:
        return list(VALIDATION_CASES.values())
    out = []
    for n in names:
        if n not in VALIDATION_CASES:
            raise InputError(f"unknown validation case {n!r}; cases: {', '.join(VALIDATION_CASES)}")
        if VALIDATION_CASES[n] not in out:
            out.append(VALIDATION_CASES[n])
    return out
