"""Linear wave theory for wave makers: dispersion, paddle transfer functions, spectra, wave components.

Plain functions and data (no simulation code), used by the paddle motions of `shoal.motions`:

* `dispersion`: the wavenumber of linear waves (`wavenumber`, `wavenumbers`) and their group velocity;
* `transfer`: wave height over paddle stroke of a piston and of a flap (Biesel & Suquet 1951);
* `spectra`: JONSWAP, Pierson-Moskowitz and tabulated variance density spectra (case-file specs);
* `components`: a spectrum cut into sinusoidal components (random phases, or focused), and the linear
  surface elevation they make.
"""

from .components import WaveComponents, focused_components, frequency_grid, random_phase_components
from .dispersion import GRAVITY, group_velocity, wavenumber, wavenumbers
from .spectra import SPECTRA, AnySpectrum, FileSpectrum, JonswapSpectrum, PiersonMoskowitzSpectrum, Spectrum
from .transfer import flap_height_to_stroke, piston_height_to_stroke

__all__ = ["GRAVITY", "SPECTRA", "AnySpectrum", "FileSpectrum", "JonswapSpectrum", "PiersonMoskowitzSpectrum",
           "Spectrum", "WaveComponents", "flap_height_to_stroke", "focused_components", "frequency_grid",
           "group_velocity", "piston_height_to_stroke", "random_phase_components", "wavenumber", "wavenumbers"]
