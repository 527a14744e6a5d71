"""Time integrators. Each reads like its algorithm: sort, rates, dt, update."""

from .predictor_corrector import PredictorCorrector
from .symplectic import Symplectic
from .verlet import Verlet

INTEGRATORS = {"verlet": Verlet, "symplectic": Symplectic, "predictor_corrector": PredictorCorrector}


def make_integrator(model):
    """The integrator named by ``model.options.integrator``."""
    return INTEGRATORS[model.options.integrator](model)


__all__ = ["Verlet", "Symplectic", "PredictorCorrector", "make_integrator"]
