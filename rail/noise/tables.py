"""CNOSSOS-EU railway rolling-noise tables (Annex II of Directive 2002/49/EC, Appendix G), as data.

The tables of Appendix G that rolling noise needs, each with the instrument it comes from and the
stored text it was transcribed from or checked against (docs/noise.md, "Where the tables come
from"). Values are in dB exactly as printed; nothing here is computed.

Numbering. Commission Directive (EU) 2015/996 printed one Table G-1 (wheel then rail roughness),
G-2 (contact filter) and G-3 (transfer functions). The corrigendum of OJ L 5, 10.1.2018 re-issued
Appendix G and Commission Delegated Directive (EU) 2021/1226, Annex point (20), replaced the rail
roughness, the contact filter and the track transfer function among others. This module names the
tables as the issue and the public implementations do: G-1a wheel roughness, G-1b rail roughness,
G-2 contact filter A_3, G-3a track transfer L_H,TR, G-3b vehicle (wheel) transfer L_H,VEH, G-3c
superstructure transfer L_H,VEH,SUP. (The Official Journal prints the two roughness tables under
the one number G-1 and the three transfer functions under G-3; the letters are shorthand.)

Grids. Tables G-1b and G-2 are given on the 35 one-third-octave wavelength bands 2000 mm .. 0.8 mm
(WAVELENGTH_LABELS_MM, exact centres 10^(-n/10) m, n = -3..31); Table G-1a on the 32 bands
1000 mm .. 0.8 mm, printing 125, 12.5, 3.15 and 1.25 mm as 120, 12, 3.2 and 1.2 mm
(WHEEL_WAVELENGTH_LABELS_MM: the same bands, n = 0..31); Tables G-3a..c on the 24 one-third-octave
frequency bands 50 Hz .. 10 kHz (FREQUENCY_LABELS_HZ).

Not transcribed (not needed for rolling noise): Table G-4 impact roughness, G-5 traction, G-6
aerodynamic noise, G-7 bridge transfer, the vehicle and track descriptors' other digits.

Sources (stored copies read for this transcription; docs/noise.md says which value was checked
against which):

* [OJ-2015] Commission Directive (EU) 2015/996, Annex, Appendix G, Table G-1, as published at
  legislation.gov.uk/eudr/2015/996/annex/appendix/G (the EU text as it stood; the wheel-roughness
  columns and the 2015 rail-roughness columns are printed there).
* [PH] phonometry (github.com/jmrplens/phonometry, MIT), src/phonometry/environment/sources/
  cnossos_rail.py at commit 0bdfbf9: a transcription of the consolidated text (2015/996 with the
  2018 corrigendum and 2021/1226), read as a second transcription, its code not used.
* [NM] NoiseModelling (github.com/Universite-Gustave-Eiffel/NoiseModelling, GPL-3),
  noisemodelling-emission/.../railway/RailwayEmissionCnossos.json at commit 35d2da1b, entries "EU*":
  a third, independent transcription (JSON data), its code not used.

The Official Journal text of Delegated Directive (EU) 2021/1226 itself was not found in any stored
source; the tables it replaced (G-1b, G-2, G-3a) rest on [PH] and [NM], which agree value for value
(tests/test_noise.py pins every value against a second, row-wise copy taken from [NM]).
"""

from __future__ import annotations

__all__ = ["A_WEIGHTING", "CONTACT_FILTER", "FREQUENCY_LABELS_HZ", "PAD_CLASSES_MN_PER_M", "RAIL_ROUGHNESS",
           "SOURCES", "SUPERSTRUCTURE_TRANSFER", "TRACK_TRANSFER", "VEHICLE_TRANSFER",
           "WAVELENGTH_LABELS_MM", "WHEEL_ROUGHNESS", "WHEEL_WAVELENGTH_LABELS_MM"]

# Nominal centre wavelengths [mm] of Tables G-1b and G-2 (2000 mm .. 0.8 mm, 35 bands, n = -3..31)
WAVELENGTH_LABELS_MM = (2000.0, 1600.0, 1250.0, 1000.0, 800.0, 630.0, 500.0, 400.0, 315.0, 250.0, 200.0, 160.0,
                        125.0, 100.0, 80.0, 63.0, 50.0, 40.0, 31.5, 25.0, 20.0, 16.0, 12.5, 10.0, 8.0, 6.3, 5.0,
                        4.0, 3.15, 2.5, 2.0, 1.6, 1.25, 1.0, 0.8)

# Table G-1a's wavelength labels [mm] as printed (1000 mm .. 0.8 mm, 32 bands, n = 0..31)
WHEEL_WAVELENGTH_LABELS_MM = (1000.0, 800.0, 630.0, 500.0, 400.0, 315.0, 250.0, 200.0, 160.0, 120.0, 100.0, 80.0,
                              63.0, 50.0, 40.0, 31.5, 25.0, 20.0, 16.0, 12.0, 10.0, 8.0, 6.3, 5.0, 4.0, 3.2, 2.5,
                              2.0, 1.6, 1.2, 1.0, 0.8)

# Nominal one-third-octave centre frequencies [Hz] of Tables G-3a..c (50 Hz .. 10 kHz, 24 bands)
FREQUENCY_LABELS_HZ = (50.0, 63.0, 80.0, 100.0, 125.0, 160.0, 200.0, 250.0, 315.0, 400.0, 500.0, 630.0, 800.0,
                       1000.0, 1250.0, 1600.0, 2000.0, 2500.0, 3150.0, 4000.0, 5000.0, 6300.0, 8000.0, 10000.0)

# Table G-1a: wheel roughness L_r,VEH [dB re 1 um] by brake type (digit 3 of the vehicle descriptor:
# c cast-iron tread brake, k composite or sinter tread brake, n non-tread braked: disc, drum,
# magnetic), on WHEEL_WAVELENGTH_LABELS_MM. Printed in [OJ-2015] Table G-1; not replaced by 2021/1226
# (its point (20)(a) replaces the second table of G-1, the rail roughness) [PH].
WHEEL_ROUGHNESS = {
    "cast_iron": (2.2, 2.2, 2.2, 2.2, 2.2, 2.2, 2.2, 2.2, 2.4, 0.6, 2.6, 5.8, 8.8, 11.1, 11.0, 9.8, 7.5, 5.1, 3.0,
                  1.3, 0.2, -0.7, -1.2, -1.0, 0.3, 0.2, 1.3, 3.1, 3.1, 3.1, 3.1, 3.1),
    "composite": (-4.0, -4.0, -4.0, -4.0, -4.0, -4.0, -4.0, -4.0, -4.0, -4.0, -4.0, -4.3, -4.6, -4.9, -5.2, -6.3,
                  -6.8, -7.2, -7.3, -7.3, -7.1, -6.9, -6.7, -6.0, -3.7, -2.4, -2.6, -2.5, -2.5, -2.5, -2.5, -2.5),
    "disc": (-5.9, -5.9, -5.9, -5.9, -5.9, -5.9, 2.3, 2.8, 2.6, 1.2, 2.1, 0.9, -0.3, -1.6, -2.9, -4.9, -7.0, -8.6,
             -9.3, -9.5, -10.1, -10.3, -10.3, -10.8, -10.9, -9.5, -9.5, -9.5, -9.5, -9.5, -9.5, -9.5),
}

# Table G-1b: rail roughness L_r,TR [dB re 1 um] by the roughness digit of the track descriptor, on
# WAVELENGTH_LABELS_MM, as replaced by 2021/1226 point (20)(a) [PH], [NM]. E: "EN ISO 3095:2013" (well
# maintained and very smooth); M: "average network" (normally maintained, smooth). The classes N and
# B carry no spectrum in Appendix G.
RAIL_ROUGHNESS = {
    "E": (17.1, 17.1, 17.1, 17.1, 17.1, 17.1, 17.1, 17.1, 15.0, 13.0, 11.0, 9.0, 7.0, 4.9, 2.9, 0.9, -1.1, -3.2,
          -5.0, -5.6, -6.2, -6.8, -7.4, -8.0, -8.6, -9.2, -9.8, -10.4, -11.0, -11.6, -12.2, -12.8, -13.4, -14.0,
          -14.0),
    "M": (35.0, 31.0, 28.0, 25.0, 23.0, 20.0, 17.0, 13.5, 10.5, 9.0, 6.5, 5.5, 5.0, 3.5, 2.0, 0.1, -0.2, -0.3,
          -0.8, -3.0, -5.0, -7.0, -8.0, -9.0, -10.0, -12.0, -13.0, -14.0, -15.0, -16.0, -17.0, -18.0, -19.0, -19.0,
          -19.0),
}

_Z11 = (0.0,) * 11

# Table G-2: contact filter A_3 [dB] by (wheel load [kN], wheel diameter [mm]), on WAVELENGTH_LABELS_MM,
# as replaced by 2021/1226 point (20)(b) [PH], [NM] (2021 reads "wheel load" where 2015 read "axle
# load" [PH]; [NM] labels the same columns "wheel load").
CONTACT_FILTER = {
    (50.0, 360.0): _Z11 + (0.0, 0.0, 0.0, -0.1, -0.2, -0.3, -0.6, -1.0, -1.8, -3.2, -5.4, -8.7, -12.2, -16.7, -17.7,
                           -17.8, -20.7, -22.1, -22.8, -24.0, -24.5, -24.7, -27.0, -27.8),
    (50.0, 680.0): _Z11 + (0.0, 0.0, -0.1, -0.2, -0.3, -0.7, -1.2, -2.0, -4.1, -6.0, -9.2, -13.8, -17.2, -17.7,
                           -18.6, -21.5, -22.3, -23.1, -24.4, -24.5, -25.0, -28.0, -28.8, -29.6),
    (50.0, 920.0): _Z11 + (0.0, -0.1, -0.1, -0.3, -0.6, -1.1, -1.3, -3.5, -5.3, -8.0, -12.0, -16.8, -17.7, -18.0,
                           -21.5, -21.8, -22.8, -24.0, -24.5, -25.0, -27.3, -28.1, -28.9, -29.7),
    (25.0, 920.0): _Z11 + (0.0, 0.0, 0.0, -0.1, -0.3, -0.5, -1.1, -1.8, -3.3, -5.3, -7.9, -12.8, -16.8, -17.7, -18.2,
                           -20.5, -22.0, -22.8, -24.2, -24.5, -25.0, -27.4, -28.2, -29.0),
    (100.0, 920.0): _Z11 + (-0.1, -0.2, -0.3, -0.6, -1.0, -1.8, -3.2, -5.4, -8.7, -12.2, -16.7, -17.7, -17.8, -20.7,
                            -22.1, -22.8, -24.0, -24.5, -24.7, -27.0, -27.8, -28.6, -29.4, -30.2),
}

# Table G-3a: track transfer function L_H,TR [dB, sound power per axle re 1 pW, for a roughness of
# 0 dB re 1 um] by (sleeper, pad class), on FREQUENCY_LABELS_HZ, as replaced by 2021/1226 point
# (20)(c) [PH], [NM]. ("wooden", None): wooden sleepers; ("direct", None): direct fastening on bridges.
TRACK_TRANSFER = {
    ("monoblock", "soft"): (53.3, 59.3, 67.2, 75.9, 79.2, 81.8, 84.2, 88.6, 91.0, 94.5, 97.0, 99.2, 104.0, 107.1,
                            108.3, 108.5, 109.7, 110.0, 110.0, 110.0, 110.3, 110.0, 110.1, 110.6),
    ("monoblock", "medium"): (50.9, 57.8, 66.5, 76.8, 80.9, 83.3, 85.8, 90.0, 91.6, 93.9, 95.6, 97.4, 101.7, 104.4,
                              106.0, 106.8, 108.3, 108.9, 109.1, 109.4, 109.9, 109.9, 110.3, 111.0),
    ("monoblock", "hard"): (50.1, 57.2, 66.3, 77.2, 81.6, 84.0, 86.5, 90.7, 92.1, 94.3, 95.8, 97.0, 100.3, 102.5,
                            104.2, 105.4, 107.1, 107.9, 108.2, 108.7, 109.4, 109.7, 110.4, 111.4),
    ("biblock", "soft"): (50.9, 56.6, 64.3, 72.3, 75.4, 78.5, 81.8, 86.6, 89.1, 91.9, 94.5, 97.5, 104.0, 107.9,
                          108.9, 108.8, 109.8, 110.2, 110.1, 110.1, 110.3, 109.9, 110.0, 110.4),
    ("biblock", "medium"): (50.0, 56.1, 64.1, 72.5, 75.8, 79.1, 83.6, 88.7, 89.6, 89.7, 90.6, 93.8, 100.6, 104.7,
                            106.3, 107.1, 108.8, 109.3, 109.4, 109.7, 110.0, 109.8, 110.0, 110.5),
    ("biblock", "hard"): (49.8, 55.9, 64.0, 72.5, 75.9, 79.4, 84.4, 89.7, 90.2, 90.2, 90.8, 93.1, 97.9, 101.1, 103.4,
                          105.4, 107.7, 108.5, 108.7, 109.1, 109.6, 109.6, 109.9, 110.6),
    ("wooden", None): (44.0, 51.0, 59.9, 70.8, 75.1, 76.9, 77.2, 80.9, 85.3, 92.5, 97.0, 98.7, 102.8, 105.4, 106.5,
                       106.4, 107.5, 108.1, 108.4, 108.7, 109.1, 109.1, 109.5, 110.2),
    ("direct", None): (75.4, 77.4, 81.4, 87.1, 88.0, 89.7, 83.4, 87.7, 89.8, 97.5, 99.0, 100.8, 104.9, 111.8, 113.9,
                       115.5, 114.9, 118.2, 118.3, 118.4, 118.9, 117.5, 117.9, 118.6),
}

# Table G-3b: vehicle (wheel) transfer function L_H,VEH [dB per axle] by wheel diameter [mm], no wheel
# measure, on FREQUENCY_LABELS_HZ; unchanged since 2015/996 (2021/1226 corrected only the band labels
# 316, 3160, 6350 Hz to 315, 3150, 6300 Hz) [PH], [NM].
VEHICLE_TRANSFER = {
    920.0: (75.4, 77.3, 81.1, 84.1, 83.3, 84.3, 86.0, 90.1, 89.8, 89.0, 88.8, 90.4, 92.4, 94.9, 100.4, 104.6, 109.6,
            114.9, 115.0, 115.0, 115.5, 115.6, 116.0, 116.7),
    840.0: (75.4, 77.3, 81.1, 84.1, 82.8, 83.3, 84.1, 86.9, 87.9, 89.9, 90.9, 91.5, 91.5, 93.0, 98.7, 101.6, 107.6,
            111.9, 114.5, 114.5, 115.0, 115.1, 115.5, 116.2),
    680.0: (75.4, 77.3, 81.1, 84.1, 82.8, 83.3, 83.9, 86.3, 88.0, 92.2, 93.9, 92.5, 90.9, 90.4, 93.2, 93.5, 99.6,
            104.9, 108.0, 111.0, 111.5, 111.6, 112.0, 112.7),
    1200.0: (75.4, 77.3, 81.1, 84.1, 82.8, 83.3, 84.5, 90.4, 90.4, 89.9, 90.1, 91.3, 91.5, 93.6, 100.5, 104.6, 115.6,
             115.9, 116.0, 116.0, 116.5, 116.6, 117.0, 117.7),
}

# Table G-3c: superstructure transfer L_H,VEH,SUP [dB per axle] of the one tabulated superstructure
# (freight wagons, "EU standard"): 0 dB in every band [PH], [NM].
SUPERSTRUCTURE_TRANSFER = (0.0,) * 24

# Rail pad classes by dynamic stiffness [MN/m] (digit 3 of the track descriptor, Table [2.3.b]):
# soft 150-250, medium 250-800, hard 800-1000 MN/m. 2021/1226 point (3) replaced "acoustic"
# stiffness by "dynamic" stiffness and named the class "hard" [PH]. Only [PH] states the ranges
# among the stored sources; [NM] names the classes (soft, medium, stiff) without ranges.
PAD_CLASSES_MN_PER_M = {"soft": (150.0, 250.0), "medium": (250.0, 800.0), "hard": (800.0, 1000.0)}

# A-weighting [dB] at the nominal one-third-octave frequencies 50 Hz .. 10 kHz, IEC 61672-1:2013
# Table 3 (the standard rounds the analytic weighting at the exact base-ten frequencies to 0.1 dB;
# tests/test_noise.py recomputes every value from the standard's pole frequencies).
A_WEIGHTING = (-30.2, -26.2, -22.5, -19.1, -16.1, -13.4, -10.9, -8.6, -6.6, -4.8, -3.2, -1.9, -0.8, 0.0, 0.6, 1.0,
               1.2, 1.3, 1.2, 1.0, 0.5, -0.1, -1.1, -2.5)

SOURCES = {
    "WHEEL_ROUGHNESS": "Table G-1 (wheel roughness, here G-1a) of Commission Directive (EU) 2015/996, Annex, "
                       "Appendix G, "
                       "not replaced by Delegated Directive (EU) 2021/1226; official text: legislation.gov.uk/eudr/2015/996/"
                       "annex/appendix/G; cross-checked against phonometry cnossos_rail.py (0bdfbf9)",
    "RAIL_ROUGHNESS": "Table G-1b (rail roughness) as replaced by Delegated Directive (EU) 2021/1226, Annex point (20)(a); "
                      "transcriptions: phonometry cnossos_rail.py (0bdfbf9), NoiseModelling RailwayEmissionCnossos.json "
                      "(35d2da1b, RailRoughness EU3/EU4); the Official Journal text of 2021/1226 was not in the stored sources",
    "CONTACT_FILTER": "Table G-2 (contact filter A_3) as replaced by Delegated Directive (EU) 2021/1226, Annex point (20)(b); "
                      "transcriptions: phonometry (0bdfbf9), NoiseModelling (35d2da1b, ContactFilter EU3-EU7)",
    "TRACK_TRANSFER": "Table G-3a (track transfer L_H,TR) as replaced by Delegated Directive (EU) 2021/1226, Annex point "
                      "(20)(c); transcriptions: phonometry (0bdfbf9), NoiseModelling (35d2da1b, TrackTransfer EU3-EU10)",
    "VEHICLE_TRANSFER": "Table G-3b (vehicle transfer L_H,VEH) of 2015/996 as re-issued in 2018, band labels corrected by "
                        "2021/1226 point (20)(d); transcriptions: phonometry (0bdfbf9), NoiseModelling (35d2da1b, Vehicle "
                        "Transfer EU3-EU6)",
    "SUPERSTRUCTURE_TRANSFER": "Table G-3c (superstructure transfer, freight); phonometry (0bdfbf9), NoiseModelling "
                               "(35d2da1b, SuperstructureTransfer EU3)",
    "PAD_CLASSES_MN_PER_M": "Table [2.3.b], digit 3, as amended by Delegated Directive (EU) 2021/1226, Annex point (3); "
                            "ranges as transcribed by phonometry (0bdfbf9), the only stored source stating them",
    "A_WEIGHTING": "IEC 61672-1:2013, Table 3 (A-weighting at nominal frequencies), 50 Hz .. 10 kHz",
}
