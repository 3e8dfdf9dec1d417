"""The diagonal of the linearised wear feedback: wear of one train passage per unit roughness at a
wavenumber, about a reference roughness (first part of the growth-rate spectrum).

For a roughness periodic over N bays about a reference that is periodic over one bay (the smooth
rail, or any bay-periodic roughness), the linearised wear operator does not couple the Bloch classes
j mod N (the forces split into the classes, rail.interaction.solve_forces, and so does the contact
about a bay-periodic state). A small cosine of amplitude eps at the line j gives the wear
Delta W_j = R_j (eps / 2) + O(eps^2) at that line, with the complex wear rate R_j [per train passage]:

    relative growth rate per train passage   g_j = -Re R_j      (growth where g_j > 0)
    phase drift per train passage            -Im R_j            (the profile moves along the rail)

so that Z_j grows like exp(-R_j n) over n train passages. One wear evaluation over the N bays gives
R_j for one line of every class at once (the classes do not couple); the reference wear is
evaluated on the same contact grid and subtracted, so the grid-tied error cancels. Lines that are
multiples of N (the one-bay comb) also carry the parametric wear of the reference itself; their
R_j is the feedback part only.

Modules: probes (the nonlinear probes, a locked line's 2 x 2 operator, the class operator and the
result RateSpectrum), linear (the tangent of the contact march over one bay, and the pieces the
cell's tangent shares), creepage (the loop of dynamic creepage's u_bar closed about the smooth rail
for the linear method), cell (a track cell of bays whose supports differ), lines (spectrum_lines;
band_lines and settings_lines for a band resolved in frequency), spectrum (rate_spectrum) and fleet
(the traffic-weighted spectrum). Every public name is importable from rail.growth_spectrum.
"""

from .cell import cell_linear_operators, cell_rate_spectrum
from .fleet import FleetRateSpectrum, combine_spectra, fleet_rate_spectrum, fleet_spectrum_of
from .linear import linear_rates
from .lines import band_lines, settings_lines, spectrum_lines
from .probes import GridMismatch, RateSpectrum, batches, class_operator, locked_operator, wear_rates
from .spectrum import locked_kinds, rate_spectrum

__all__ = ["wear_rates", "RateSpectrum", "spectrum_lines", "rate_spectrum", "locked_operator", "class_operator",
           "FleetRateSpectrum", "fleet_rate_spectrum", "combine_spectra", "fleet_spectrum_of", "GridMismatch", "batches", "linear_rates",
           "cell_linear_operators", "cell_rate_spectrum", "locked_kinds", "band_lines", "settings_lines"]
