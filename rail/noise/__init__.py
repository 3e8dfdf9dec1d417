"""Rolling noise from the rail roughness: CNOSSOS-EU for railways (Directive 2002/49/EC Annex II,
section 2.3 and Appendix G, as replaced by Directive (EU) 2015/996, corrected in 2018 and amended by
Delegated Directive (EU) 2021/1226). docs/noise.md.

Modules: rail.noise.tables (Appendix G's rolling-noise tables as data, each with its source),
rail.noise.weighting (A-weighting of IEC 61672-1, energy sums), rail.noise.cnossos (total effective
roughness, the wavelength-to-frequency mapping, the sound power per vehicle and per metre of line),
rail.noise.rolling (a traffic over a track, the whole chain), rail.noise.own_track (the track's own
transfer from its rail receptance and decay rate, in place of Table G-3a's), rail.noise.grinding.
"""

from .cnossos import (RULES, SPEED_MAX, SPEED_MIN, check_speed, contact_filter, contact_filter_column,
                      line_sound_power, pad_class, rail_roughness_class, rail_roughness_on_bands, rolling_sound_power,
                      total_effective_roughness, track_transfer, vehicle_transfer, wavelength_to_frequency,
                      wheel_roughness)
from .rolling import RollingNoise, Track, TrafficClass, Vehicle, rolling_noise
from .weighting import a_weighting, energy_sum, overall_level

__all__ = ["RULES", "SPEED_MAX", "SPEED_MIN", "RollingNoise", "Track", "TrafficClass", "Vehicle", "a_weighting",
           "check_speed", "contact_filter", "contact_filter_column", "energy_sum", "line_sound_power",
           "overall_level", "pad_class", "rail_roughness_class", "rail_roughness_on_bands", "rolling_noise",
           "rolling_sound_power", "total_effective_roughness", "track_transfer", "vehicle_transfer",
           "wavelength_to_frequency", "wheel_roughness"]
