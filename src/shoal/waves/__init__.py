"""Wave theory for wave makers: dispersion, paddle transfer functions, spectra, wave components, second order.

Plain functions and data (no simulation code), used by the paddle motions of `shoal.motions`:

* `dispersion`: the wavenumber of linear waves (`wavenumber`, `wavenumbers`) and their group velocity;
* `transfer`: wave height over paddle stroke of a piston and of a flap (Biesel & Suquet 1951);
* `spectra`: JONSWAP, Pierson-Moskowitz and tabulated variance density spectra (case-file specs);
* `components`: a spectrum cut into sinusoidal components (random phases, or focused), and the linear
  surface elevation they make;
* `second_order`: the second-order paddle motion that suppresses spurious free waves (Schäffer 1996; Madsen
  1971 for a regular wave) and the second-order bound waves (Sharma & Dean 1981).
"""

from .components import WaveComponents, focused_components, frequency_grid, random_phase_components
from .dispersion import GRAVITY, group_velocity, wavenumber, wavenumbers
from .second_order import (BoundWaves, SecondOrderPaddle, bound_wave_transfer, bound_waves, default_modes,
                           madsen_piston_second_harmonic, paddle_transfer, regular_second_order, second_order_paddle)
from .spectra import SPECTRA, AnySpectrum, FileSpectrum, JonswapSpectrum, PiersonMoskowitzSpectrum, Spectrum
from .transfer import flap_height_to_stroke, piston_height_to_stroke

__all__ = ["GRAVITY", "SPECTRA", "AnySpectrum", "BoundWaves", "FileSpectrum", "JonswapSpectrum",
           "PiersonMoskowitzSpectrum", "SecondOrderPaddle", "Spectrum", "WaveComponents", "bound_wave_transfer",
           "bound_waves", "default_modes", "flap_height_to_stroke", "focused_components", "frequency_grid",
           "group_velocity", "madsen_piston_second_harmonic", "paddle_transfer", "piston_height_to_stroke",
           "random_phase_components", "regular_second_order", "second_order_paddle", "wavenumber", "wavenumbers"]
