"""Track characterisation datasets: what a railway noise engineer compares with site measurements.

* point receptance above a sleeper and at mid-span, with the track's characteristic frequencies;
* the moving-load receptance at the contact point against the stationary bay-averaged one;
* the vertical track decay rate in one-third-octave bands (EN 15461 estimator, ``rail.decay``).

Physics comes from ``rail.track``, ``rail.moving`` and ``rail.decay``; units and long names are
attached here.  Each function returns an xarray Dataset whose every variable and coordinate
carries ``units`` and ``long_name``; ``rail.setup.io.finalize`` adds the configuration and versions.
Complex receptances are stored as real and imaginary parts, m/N, displacement and force positive
downwards, time factor exp(+i omega t).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .. import decay, moving
from .. import track as T
from ..track import Track
from ..setup.io import data_var

__all__ = ["track_receptance", "moving_receptance", "track_decay_rate", "measured_decay_rate"]

_CONVENTION = "displacement per unit force, both positive downwards; time factor exp(+i omega t)"



def _track_attrs(track: Track, name: str) -> dict:
    return {"track_name": name, "sleeper_spacing_m": track.L, "damping_model": track.damping, "convention": _CONVENTION}


def track_receptance(track: Track, name: str = "default", f_min: float = 10.0, f_max: float = 5000.0,
                     points: int = 1000, rtol: float = 1e-7) -> xr.Dataset:
    """Vertical point receptance above a sleeper (x = 0) and at mid-span (x = L/2), m/N.

    Frequencies: ``points`` log-spaced from f_min to f_max (Hz) plus the characteristic
    frequencies themselves, so the plotted peaks reach their maxima.  The characteristic
    frequencies (``rail.track.characteristic_frequencies``, from the receptance's maxima) and the
    closed-form pinned-pinned frequency of a Timoshenko span L are attributes, Hz.

    Parameters
    ----------
    track : Track
    name : str
        The track's name (its scenario), in the attributes.
    f_min, f_max : float
        Frequency range [Hz].
    points : int
        Log-spaced frequencies [-].
    rtol : float
        Relative tolerance of the receptance integrals [-].

    Returns
    -------
    xr.Dataset
        Receptance above a sleeper and at mid-span [m/N] over frequency [Hz].
    """
    fc = T.characteristic_frequencies(track)
    extra = [v for v in fc.values() if np.isfinite(v) and f_min <= v <= f_max]
    f = np.unique(np.concatenate([np.geomspace(f_min, f_max, points), extra]))
    x = np.array([0.0, track.L / 2])
    alpha = np.array([T.stationary_receptance(x, x, 2 * np.pi * fi, track, rtol=rtol) for fi in f])
    sl, mid = alpha[:, 0], alpha[:, 1]
    return xr.Dataset(
        {
            "receptance_sleeper_real": data_var("frequency", sl.real, "m/N", "real part of the vertical point receptance above a sleeper, x = 0"),
            "receptance_sleeper_imag": data_var("frequency", sl.imag, "m/N",
                                                "imaginary part of the vertical point receptance above a sleeper, x = 0"),
            "receptance_midspan_real": data_var("frequency", mid.real, "m/N", "real part of the vertical point receptance at mid-span, x = L/2"),
            "receptance_midspan_imag": data_var("frequency", mid.imag, "m/N", "imaginary part of the vertical point receptance at mid-span, x = L/2"),
        },
        coords={"frequency": data_var("frequency", f, "Hz", "frequency")},
        attrs={
            **_track_attrs(track, name),
            "track_on_ballast_Hz": fc["track_on_ballast"],
            "out_of_phase_Hz": fc["out_of_phase"],
            "pinned_pinned_Hz": fc["pinned_pinned"],
            "pinned_pinned_closed_form_Hz": T.pinned_pinned_frequency(track),
            "characteristic_frequencies": "track_on_ballast_Hz and out_of_phase_Hz: first and second maxima of "
            "|receptance| above a sleeper; pinned_pinned_Hz: maximum at mid-span above the out-of-phase one "
            "(rail.track.characteristic_frequencies); pinned_pinned_closed_form_Hz: first bending mode of a simply "
            "supported Timoshenko span L (rail.track.pinned_pinned_frequency)",
            "quadrature_rtol": rtol,
        },
    )


def moving_receptance(
    track: Track,
    speeds,
    name: str = "default",
    f_min: float = 100.0,
    f_max: float = 3000.0,
    points: int = 150,
    bay_points: int = 16,
    rtol: float = 1e-4,
) -> xr.Dataset:
    """Moving-load receptance at the contact point, a_0(Omega), for each speed, beside the
    stationary point receptance averaged over the load position in a bay, m/N.

    a_0 is the n = 0 coefficient of ``rail.moving.moving_coefficients`` at offset 0: the part of
    the rail displacement under a load F exp(i Omega t) moving at speed V that has the load's own
    frequency.  As V -> 0 it tends to the bay average (1/L) int_0^L alpha(x0, x0) dx0, taken here
    as the mean over ``bay_points`` equally spaced load positions (periodic trapezoidal rule).
    Excitation frequency f = Omega / 2 pi: ``points`` log-spaced from f_min to f_max (Hz).

    Parameters
    ----------
    track : Track
    speeds : array_like
        Load speeds V [m/s].
    name : str
        The track's name (its scenario), in the attributes.
    f_min, f_max : float
        Excitation frequency range [Hz].
    points : int
        Log-spaced frequencies [-].
    bay_points : int
        Load positions of the bay average [-].
    rtol : float
        Relative tolerance of the moving-load integrals [-].

    Returns
    -------
    xr.Dataset
        a_0 [m/N] over speed [m/s] and frequency [Hz], beside the stationary bay average [m/N].
    """
    speeds = np.atleast_1d(np.asarray(speeds, dtype=float))
    f = np.geomspace(f_min, f_max, points)
    a0 = np.empty((len(speeds), len(f)), dtype=complex)
    err = np.empty(a0.shape)
    for i, V in enumerate(speeds):
        for j, fj in enumerate(f):
            _, a, e = moving.moving_coefficients(track, V, 2 * np.pi * fj, 0, offset=0.0, rtol=rtol)
            a0[i, j], err[i, j] = a[0], e[0]
    x0 = np.arange(bay_points) * track.L / bay_points
    bay = np.array([np.mean(T.stationary_receptance(x0, x0, 2 * np.pi * fj, track)) for fj in f])
    return xr.Dataset(
        {
            "moving_receptance_real": data_var(("speed", "frequency"), a0.real, "m/N",
                                               "real part of the moving-load receptance a_0(Omega) at the contact point"),
            "moving_receptance_imag": data_var(("speed", "frequency"), a0.imag, "m/N",
                                               "imaginary part of the moving-load receptance a_0(Omega) at the contact point"),
            "moving_receptance_error": data_var(("speed", "frequency"), err, "m/N", "estimated absolute error of a_0 from the wavenumber quadrature"),
            "stationary_receptance_real": data_var("frequency", bay.real, "m/N",
                                                   "real part of the stationary point receptance alpha(x0, x0) "
                                                   "averaged over the load position x0 in a bay"),
            "stationary_receptance_imag": data_var("frequency", bay.imag, "m/N",
                                                   "imaginary part of the stationary point receptance alpha(x0, x0) "
                                                   "averaged over the load position x0 in a bay"),
            "sleeper_passing_frequency": data_var("speed", speeds / track.L, "Hz", "sleeper-passing frequency V / L"),
        },
        coords={
            "speed": data_var("speed", speeds, "m/s", "train speed V"),
            "frequency": data_var("frequency", f, "Hz", "excitation frequency Omega / 2 pi"),
        },
        attrs={
            **_track_attrs(track, name),
            "pinned_pinned_closed_form_Hz": T.pinned_pinned_frequency(track),
            "bay_points": int(bay_points),
            "quadrature_rtol": rtol,
        },
    )


def track_decay_rate(track: Track, name: str = "default", **kwargs) -> xr.Dataset:
    """Vertical track decay rate in one-third-octave bands, dB/m, excited above a sleeper and at
    mid-span, with the response positions of both schemes of ``rail.decay.decay_distances``
    (``rail.decay.track_decay_rate``, EN 15461); keyword arguments go to that function.

    ``decay_rate`` uses the EN 15461-like positions (far positions at the excitation point's place
    in the bay, as measured); ``decay_rate_bay_sampled`` the positions that sample the whole bay.
    Their difference shows how much the estimator depends on where in the bay the far positions
    lie.

    Parameters
    ----------
    track : Track
    name : str
        The track's name (its scenario), in the attributes.
    **kwargs
        Passed to rail.decay.track_decay_rate (bands, positions, tolerance).

    Returns
    -------
    xr.Dataset
        Decay rates [dB/m] per band centre [Hz] and excitation position, the response positions [m].
    """
    r = decay.track_decay_rate(track, **kwargs)
    exc, band, pos = "excitation_position", "band_centre", "position"
    formula = "4.343 / sum_n |A(x_n)|^2 / |A(x_0)|^2 dx_n"
    data = {}
    for k, scheme in enumerate(r.schemes):
        suffix = "" if k == 0 else f"_{scheme}"
        what = {
            "en15461": "far positions at the excitation point's place in the bay, as EN 15461",
            "bay_sampled": "far positions sampling the whole bay",
            "custom": "positions given",
        }[scheme]
        data[f"decay_rate{suffix}"] = data_var((exc, band), r.decay_rate[k], "dB/m",
                                               f"vertical track decay rate, EN 15461 {formula}; {what}", position_scheme=scheme)
        data[f"position_weight{suffix}"] = data_var(pos, r.weights[k], "m",
                                                    f"dx_n of the EN 15461 sum (trapezoidal rule); 0 where unused; {what}", position_scheme=scheme)
        data[f"attenuation_at_last_position{suffix}"] = data_var((exc, band), r.attenuation[k], "dB",
                                                                 f"fall of the band-averaged |A|^2 from the excitation point to the last "
                                                                 f"position; {what}",
                                                                 position_scheme=scheme)
    data.update(
        {
            "transfer_level": data_var((exc, band, pos), r.level, "dB", "band-averaged |A(x_n)|^2 relative to |A(x_0)|^2"),
            "band_centre_exact": data_var(band, r.bands.centre, "Hz", "exact band centre 1000 * 10^(n/10)"),
            "band_lower": data_var(band, r.bands.lower, "Hz", "lower band edge"),
            "band_upper": data_var(band, r.bands.upper, "Hz", "upper band edge"),
            "band_frequency": data_var((band, "sample"), r.frequencies, "Hz", "frequencies over which |A|^2 is averaged in each band"),
        }
    )
    return xr.Dataset(
        data,
        coords={
            exc: data_var(exc, r.excitation, "m", "excitation point x_0 measured from a sleeper (0: above a sleeper, L/2: mid-span)"),
            band: data_var(band, r.bands.nominal, "Hz", "nominal one-third-octave band centre frequency"),
            pos: data_var(pos, r.distances, "m", "response position x_n - x_0 along the rail from the excitation point"),
            "sample": data_var("sample", np.arange(r.frequencies.shape[1]), "1", "index of the frequency within the band"),
        },
        attrs={
            **_track_attrs(track, name),
            "frequencies_per_band": int(r.frequencies.shape[1]),
            "position_schemes": ", ".join(r.schemes),
            "method": "EN 15461:2008+A1:2010 decay-rate estimator applied to the model's transfer receptances "
            "A(x_n) = alpha(x_0 + d_n, x_0) (rail.track.stationary_receptance); |A|^2 averaged over equally spaced "
            "frequencies in each band; positions from x_0 in +x (the track is symmetric about a sleeper and about "
            "mid-span); dx_n trapezoidal weights; a position is used by a scheme where its position_weight > 0",
            "standard": "EN 15461:2008+A1:2010, Railway applications - Noise emission - Characterisation of the dynamic "
            "properties of track sections for pass by noise measurements",
        },
    )


def measured_decay_rate(measured: decay.MeasuredDecayRate) -> xr.Dataset:
    """A measured decay rate (``rail.decay.read_measured_decay_rate``) as a dataset on its own
    band coordinate, ready to merge beside the computed one.

    Parameters
    ----------
    measured : rail.decay.MeasuredDecayRate
        Band centres [Hz] and decay rates [dB/m] of a measurement, and its file.

    Returns
    -------
    xr.Dataset
        measured_decay_rate [dB/m] on measured_band_centre [Hz].
    """
    return xr.Dataset(
        {"measured_decay_rate": data_var("measured_band_centre", measured.decay_rate, "dB/m", "measured vertical track decay rate",
                                         source_file=measured.source)},
        coords={"measured_band_centre": data_var("measured_band_centre", measured.band_centre, "Hz",
                                                 "band centre frequency of the measured decay rate")},
    )
