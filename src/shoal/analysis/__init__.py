"""Analysis of simulation results against reference data."""

from .bore import (arrival_time, bore_from_inflow, celerity, crest_speed_ratio, front_position, level_behind,
                   undulations, volume_depth)
from .front import outside_band, surge_front
from .mean_flow import depth_average, mse, period_average, rmse, set_up, vorticity
from .reference import load_reference, mean_relative_error
from .reflection import IrregularReflection, irregular_reflection
from .runup import Overtopping, RunupStatistics, overtopping, runup_statistics
from .spectral import Spectrum, band_ratios, wave_spectrum
from .waves import ReflectionAnalysis, WaveStatistics, harmonic_amplitude, phase_speed, reflection_analysis, wave_statistics
from .zero_crossing import ZeroCrossingStatistics, zero_crossing_statistics

__all__ = ["surge_front", "outside_band", "load_reference", "mean_relative_error", "period_average", "depth_average", "set_up",
           "vorticity", "rmse", "mse", "bore_from_inflow", "arrival_time", "celerity", "volume_depth", "front_position",
           "level_behind", "undulations", "crest_speed_ratio", "wave_statistics", "phase_speed", "WaveStatistics",
           "reflection_analysis", "harmonic_amplitude", "ReflectionAnalysis", "wave_spectrum", "Spectrum", "band_ratios",
           "zero_crossing_statistics", "ZeroCrossingStatistics", "irregular_reflection", "IrregularReflection",
           "runup_statistics", "RunupStatistics", "overtopping", "Overtopping"]
