"""Roughness growth over many wheel passages, with progress and resumable checkpoints (sec. 5).

One update:

1. compute the wear of one train passage at the current roughness (rail.chain.train_wear: the
   normal forces of every wheel, then the wheels roll over the bay in turn, leading wheel first,
   each on the profile the one before it left);
2. remove that wear ``passages_per_update / n_wheels`` times (eq 54, Delta Z_0 = 0).

This module is the integrator (steps, error estimates, checkpoints); the model it integrates is
handed in as a function.

Passages are counted as wheel passages, as in the report ("one passage of the two bogies equals
four wheel passages"). The roughness is saved every ``save_every`` wheel passages. Levels are
rms levels in dB re 1 um: a component Z_k, Z_{-k} has amplitude 2 abs(Z_k) and rms sqrt(2) abs(Z_k).

The contact grid's spacing changes between updates, so that a / Delta at the bay's mean
half-length sweeps one unit over the updates in a golden-ratio (low-discrepancy) sequence
(grid_phase; each grid serves two successive updates, so that the update-error estimate of every
second update compares two wear rates on one grid).
The discretisation's small remaining error that is periodic in a / Delta (where the patch edges
fall between grid nodes) then averages out instead of building up as false roughness
(docs/contact.md). Shifting the grid against the supports would not average it: the error depends
on a / Delta, which a shift leaves unchanged.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import time
from dataclasses import dataclass
from dataclasses import field as dataclass_field
from pathlib import Path

import numpy as np

from .contact import ContactError
from .interaction import ContactLossError, Roughness

__all__ = ["GrowthSettings", "GrowthHistory", "GrowthStepError", "CheckpointWriteError", "grid_phase", "levels_dB", "run_growth", "step_error",
           "DB_PER_NEPER", "BandGrowth", "band_growth", "BAND_GROWTH_SAVES"]

DB_PER_NEPER = 20 * np.log10(np.e)  # dB of amplitude per unit of ln(amplitude)

GOLDEN = (np.sqrt(5) - 1) / 2


def grid_phase(update: int) -> float:
    """Contact grid phase of an update (rail.wear.bay_wear grid_phase).

    A golden-ratio (low-discrepancy) sequence over [0, 1), each value used for two successive
    updates, so that every second update's error estimate compares two wear rates on the same grid
    (a difference between grids would be the grid-tied error, not the update error).

    Parameters
    ----------
    update : int
        Update number from 0 [-].

    Returns
    -------
    float
        Phase in [0, 1) [-].
    """
    return float(((update // 2) * GOLDEN) % 1.0)


@dataclass(frozen=True)
class GrowthSettings:
    """Growth-loop settings (config key ``growth``).

    Attributes
    ----------
    passages : total wheel passages [-]
    passages_per_update : wheel passages whose wear is applied per force/contact update [-]
    save_every : wheel passages between saved profiles (a multiple of passages_per_update) [-]
    vary_grid_spacing : vary the contact grid spacing between updates so that a / Delta sweeps
                           one unit (averages the grid-tied error; rail.wear.bay_wear grid_phase)
    step_tolerance : largest accepted estimate of one update's error, relative to the
                           roughness [-] (see run_growth); a larger one stops the run with an error
    """

    passages: int
    passages_per_update: int
    save_every: int
    vary_grid_spacing: bool
    step_tolerance: float

    def __post_init__(self):
        if not (np.isfinite(self.step_tolerance) and self.step_tolerance > 0):
            raise ValueError(f"growth.step_tolerance = {self.step_tolerance!r} is not allowed: it must be a finite number > 0.")
        if self.save_every < 1:
            raise ValueError(f"growth.save_every = {self.save_every!r} is not allowed: it must be >= 1.")
        if self.passages_per_update < 1 or self.passages < self.passages_per_update:
            raise ValueError(
                f"growth.passages_per_update = {self.passages_per_update} is not allowed: it must lie in "
                f"[1, growth.passages = {self.passages}]."
            )
        if self.save_every % self.passages_per_update or self.passages % self.save_every:
            raise ValueError(
                f"growth.save_every = {self.save_every} must be a multiple of growth.passages_per_update = "
                f"{self.passages_per_update} and divide growth.passages = {self.passages}."
            )


@dataclass
class GrowthHistory:
    """Saved states of a growth run (run_growth).

    Attributes
    ----------
    passages : (n,) wheel passages at each save
    Z : (n, 2K+1) roughness coefficients, m
    step_error : (updates,) estimated local error of each update relative to the roughness, -; NaN
                 where the two rates compared were on different contact grids (grid_phase)
    full_slip : (updates,) largest fraction of the bay without a stick zone over the wheels, -
    stopped : '' for a run that reached its passages, else the one-line reason it stopped early (a
                 physical assumption broke: contact lost, multiple contact; run_growth).
    """

    passages: np.ndarray
    Z: np.ndarray
    step_error: np.ndarray = dataclass_field(default_factory=lambda: np.zeros(0))
    full_slip: np.ndarray = dataclass_field(default_factory=lambda: np.zeros(0))
    stopped: str = ""


def stop_message(done: int, Z0, Z, error: Exception, period: float | None = None) -> str:
    """One line: why a growth run stopped, at how many passages, and the roughness that broke it.

    The contact breaks where the rail is too curved under the wheel, so the harmonic named is the
    one with the largest curvature amplitude j^2 abs(Z_j), with its level and its change since the start;
    on a rail still smooth (every harmonic zero) the line says so instead of naming a harmonic.

    Parameters
    ----------
    done : int
        Wheel passages done [-].
    Z0, Z : ndarray, shape (2J + 1,)
        Initial and current roughness coefficients [m].
    error : Exception
        The broken assumption (its message, one line).
    period : float, optional
        Roughness period [m] (for the wavelength; else the harmonic's index is named).

    Returns
    -------
    str
    """
    J = (len(Z) - 1) // 2
    Z = np.asarray(Z)
    reason = " ".join(str(error).split())
    if not np.any(Z[J + 1:]):  # a smooth rail: no harmonic broke it (naming one at -480 dB misled)
        return (f"growth stopped at {done} passages: {reason} The rail is still smooth (no roughness harmonic), so the "
                "roughness did not cause it; every state saved up to here is kept.")
    j = int(np.argmax(np.arange(1, J + 1) ** 2 * np.abs(Z[J + 1:]))) + 1
    now, start = levels_dB(Z)[j - 1], levels_dB(Z0)[j - 1]
    where = f"wavelength {1e3 * period / j:.3g} mm" if period else f"harmonic {j} of {J}"
    change = f"{now - start:+.1f} dB since the start" if start > -400 else "absent at the start"
    return (f"growth stopped at {done} passages: {reason} The most curved roughness is at {where} "
            f"(now {now:.1f} dB re 1 µm, {change}); every state saved up to here is kept.")


def levels_dB(Z):
    """rms roughness level of each harmonic k >= 1, 20 log10(sqrt(2) abs(Z_k) / 1e-6).

    Parameters
    ----------
    Z : ndarray, shape (..., 2K + 1)
        Roughness coefficients k = -K..K [m] (eq 18).

    Returns
    -------
    ndarray, shape (..., K)
        Levels [dB re 1 µm]; a zero harmonic gives -480 dB (floor 1e-30 m).
    """
    Z = np.asarray(Z)
    K = (Z.shape[-1] - 1) // 2
    rms = np.sqrt(2) * np.abs(Z[..., K + 1 :])
    return 20 * np.log10(np.maximum(rms, 1e-30) / 1e-6)


@dataclass(frozen=True)
class BandGrowth:
    """Growth of each band (or line) over a run (band_growth).

    Attributes
    ----------
    linear_rate, linear_error : ndarray
        Amplitude growth rate and its standard error [m per 1e5 passages].
    exp_rate, exp_error : ndarray
        e-folding rate and its standard error [1 per 1e5 passages].
    law : ndarray of str
        'linear' or 'exponential', the better fit; '' where not resolved.
    linear_misfit, exp_misfit : ndarray
        rms residual of each fit relative to the band's mean amplitude [-].
    dB_rate, dB_error : ndarray
        Level growth rate at the last save and its standard error [dB per 1e5 passages], from the
        law that fits: 20 log10(e) exp_rate for an exponential, 20 log10(e) linear_rate / a(n_last)
        for a straight line (the rate of a linear growth falls as its amplitude grows).
    """

    linear_rate: np.ndarray
    linear_error: np.ndarray
    exp_rate: np.ndarray
    exp_error: np.ndarray
    law: np.ndarray
    linear_misfit: np.ndarray
    exp_misfit: np.ndarray
    dB_rate: np.ndarray
    dB_error: np.ndarray


def _line_fit(x, y):
    """Least-squares slope, its standard error and the rms residual of y = c + s x."""
    A = np.vstack([np.ones_like(x), x]).T
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    res = y - A @ coef
    dof = max(len(x) - 2, 1)
    s2 = float(res @ res) / dof
    cov = s2 * np.linalg.inv(A.T @ A)
    return coef, float(np.sqrt(cov[1, 1])), float(np.sqrt(np.mean(res**2)))


# the saved passage counts a band's growth laws need (band_growth: a line and an exponential, two
# parameters each, fitted with a residual): the start and at least two saves
BAND_GROWTH_SAVES = 3


def band_growth(passages, ms) -> BandGrowth:
    """Fit the growth of every band or line: a straight line and an exponential in its rms amplitude,
    the better one its law, and the level growth rate at the last save from that law
    (rail.studies.bands, docs/exports.md).

    Parameters
    ----------
    passages : ndarray, shape (n,)
        Wheel passages at the saves [-]; at least 3.
    ms : ndarray, shape (n, bands)
        Band mean squares [m^2] (band_mean_square); NaN columns are unresolved bands.

    Returns
    -------
    BandGrowth
    """
    n = np.asarray(passages, dtype=float) / 1e5
    if n.size < BAND_GROWTH_SAVES:
        raise ValueError(f"band growth needs at least {BAND_GROWTH_SAVES} saved passage counts, got {n.size}.")
    amp = np.sqrt(np.asarray(ms, dtype=float))
    B = amp.shape[1]
    out = {k: np.full(B, np.nan) for k in ("lr", "le", "er", "ee", "lm", "em", "dr", "de")}
    law = np.full(B, "", dtype=object)
    for b in range(B):
        a = amp[:, b]
        if not np.all(np.isfinite(a)):
            continue
        scale = max(float(np.mean(a)), 1e-300)
        (c, s), se, rms = _line_fit(n, a)
        out["lr"][b], out["le"][b], out["lm"][b] = s, se, rms / scale
        if np.all(a > 0):
            (c2, g), ge, _ = _line_fit(n, np.log(a))
            fit = np.exp(c2 + g * n)
            out["er"][b], out["ee"][b] = g, ge
            out["em"][b] = float(np.sqrt(np.mean((a - fit) ** 2))) / scale
        law[b] = "exponential" if np.isfinite(out["em"][b]) and out["em"][b] < out["lm"][b] else "linear"
        # the level growth rate at the last save from the law that fits: constant for an exponential,
        # 20 log10(e) s / a(n_last) for a straight line (falls as the amplitude grows)
        if law[b] == "exponential":
            out["dr"][b], out["de"][b] = DB_PER_NEPER * out["er"][b], DB_PER_NEPER * out["ee"][b]
        elif c + s * n[-1] > 0:
            out["dr"][b], out["de"][b] = DB_PER_NEPER * s / (c + s * n[-1]), DB_PER_NEPER * se / (c + s * n[-1])
    return BandGrowth(out["lr"], out["le"], out["er"], out["ee"], law.astype(str), out["lm"], out["em"], out["dr"], out["de"])


def _fingerprint(obj) -> str:
    return hashlib.sha256(json.dumps({"run": obj}, sort_keys=True, default=str).encode()).hexdigest()[:16]


CARRY_PREFIX = "carry:"  # the checkpoint's arrays of the wear function's carried state (run_growth's ``carry``)


def _save_checkpoint(path: Path, fingerprint: str, done: int, Z, history: GrowthHistory, update: int, rate, carry=None):
    """Everything a resumed run needs to continue as if never stopped, including the last wear
    rate (rate, for the next update's error estimate) and the wear function's carried state (carry)."""
    tmp = path.with_suffix(".tmp.npz")
    kept = {} if carry is None else {CARRY_PREFIX + k: v for k, v in carry.arrays().items()}
    try:
        np.savez(tmp, fingerprint=fingerprint, done=done, Z=Z, hist_passages=history.passages, hist_Z=history.Z, update=update,
                 step_error=history.step_error, full_slip=history.full_slip, rate=np.asarray(rate), **kept)
        os.replace(tmp, path)  # atomic: a run killed at any moment leaves the old or the new checkpoint
    except OSError as e:  # a full disk, a file-size limit, a folder made read-only: no partial file left behind
        try:
            tmp.unlink(missing_ok=True)
        except OSError:
            pass
        kept = "the previous checkpoint there is kept" if path.exists() else "no checkpoint was written yet"
        raise CheckpointWriteError(e.errno, f"could not write the checkpoint at {done} passages: {e.strerror or e} ({kept}; "
                                   "free space or give another --checkpoint, then run again to resume)", str(path)) from e


def _move_aside(path: Path, why: str) -> Path:
    """Rename a checkpoint that must not be resumed to <name>.<why>[.n] beside it (kept for inspection)."""
    target = path.with_name(f"{path.name}.{why}")
    n = 1
    while target.exists():
        target = path.with_name(f"{path.name}.{why}.{n}")
        n += 1
    os.replace(path, target)
    return target


class CheckpointWriteError(OSError):
    """A growth checkpoint could not be written (a resource problem: disk space, file size, permissions);
    its filename is the checkpoint, its strerror says what was kept."""


class GrowthStepError(RuntimeError):
    """The update step (growth.passages_per_update) is too large for growth.step_tolerance."""


def step_error(rate_before, rate_after, Z_after, train_passages: float) -> float:
    """Estimated local error of one explicit update Z' = Z - h W(Z) (eq 54), relative to the roughness.

    Parameters
    ----------
    rate_before, rate_after : ndarray
        Wear per train passage W(Z), W(Z') [m].
    Z_after : ndarray
        Roughness Z' after the update [m].
    train_passages : float
        Train passages h per update [-].

    Returns
    -------
    float
        (h / 2) norm(W(Z') - W(Z)) / norm(Z') (L2 norms over the harmonics) [-].

    Notes
    -----
    The error of the update is (h / 2) norm(W(Z') - W(Z)) to leading order (the step is first
    order), with h the train passages per update and W the wear per train passage (m). Its L2
    norm over the harmonics is divided by that of the roughness Z'. The next update computes
    W(Z') anyway, so the estimate costs nothing but one extra evaluation after the last update.
    """
    num = 0.5 * train_passages * np.linalg.norm(np.asarray(rate_after) - np.asarray(rate_before))
    return float(num / max(np.linalg.norm(Z_after), 1e-300))


def _resume(ck: Path, fp: str, on_mismatch: str, passages: int, progress, carry=None):
    """run_growth's state from its checkpoint ck: (done, Z, update, history, rate_before), or None to
    start afresh (an unreadable checkpoint, or with on_mismatch 'restart' one written for another
    fingerprint, is moved aside; without 'restart' the latter is an error). The carried state is
    restored into carry."""
    try:
        with np.load(ck, allow_pickle=False) as data:
            saved = {k: data[k] for k in ("fingerprint", "done", "Z", "update", "hist_passages", "hist_Z", "step_error",
                                          "full_slip", "rate")}
            carried = {k[len(CARRY_PREFIX):]: data[k] for k in data.files if k.startswith(CARRY_PREFIX)}
    except Exception as e:  # noqa: BLE001 - truncated, empty, random or incomplete: never resumable
        aside = _move_aside(ck, "unreadable")
        print(f"warning: checkpoint {ck} cannot be read ({type(e).__name__}: {e}); moved to {aside}, starting afresh",
              file=progress, flush=True)
        return None
    if str(saved["fingerprint"]) != fp:
        if on_mismatch != "restart":
            raise ValueError(f"checkpoint {ck} was written for another configuration or code; delete it to start afresh.")
        aside = _move_aside(ck, "other")
        print(f"checkpoint {ck} belongs to another configuration, input or code: moved to {aside}, starting afresh",
              file=progress, flush=True)
        return None
    done, Z, update = int(saved["done"]), saved["Z"].copy(), int(saved["update"])
    history = GrowthHistory(saved["hist_passages"].copy(), saved["hist_Z"].copy(), saved["step_error"].copy(),
                            saved["full_slip"].copy())
    rate_before = saved["rate"].copy()  # saved after an update, so always there
    if carry is not None:
        carry.restore(carried)
    print(f"resuming from {ck}: {done} of {passages} passages done", file=progress)
    return done, Z, update, history, rate_before


def _check_update(history: GrowthHistory, settings: GrowthSettings, train_passages: float, ck, rate_before, rate_after, Z_after,
                  passages_after: int):
    """Append the update's estimated error (step_error) to the history; GrowthStepError, naming a step
    that would pass, where it exceeds settings.step_tolerance or is not finite."""
    err = step_error(rate_before, rate_after, Z_after, train_passages)
    history.step_error = np.append(history.step_error, err)
    if not np.isfinite(err) or err > settings.step_tolerance:
        ppu = settings.passages_per_update
        suggest = max(int(ppu * settings.step_tolerance / err), 1) if np.isfinite(err) and err > 0 else 1
        raise GrowthStepError(
            f"growth.passages_per_update = {ppu} is too large: the update ending at {passages_after} passages has an "
            f"estimated error of {100 * err:.3g} % of the roughness (growth.step_tolerance = {settings.step_tolerance:g}); "
            f"use at most about {suggest} passages per update (the error is first order in the step). "
            + (f"The roughness saved up to {int(history.passages[-1])} passages is in {ck}." if ck is not None else "")
        )


def run_growth(
    train_wear,
    roughness: Roughness,
    n_wheels: int,
    settings: GrowthSettings,
    checkpoint: str | Path | None = None,
    identity: dict | None = None,
    progress=sys.stderr,
    stop_after_updates: int | None = None,
    on_mismatch: str = "error",
    period: float | None = None,
    carry=None,
) -> GrowthHistory:
    """Grow the roughness over ``settings.passages`` wheel passages (sec. 5, eq 54).

    Parameters
    ----------
    train_wear : callable
        ``train_wear(Z, grid_phase) -> (dZ, full_slip)``: the wear coefficients Delta Z_k [m] of one
        train passage at roughness Z [m] with the contact grid at ``grid_phase`` (rail.wear.bay_wear),
        and the largest fraction of the bay without a stick zone [-] (rail.chain.train_wear).
    roughness : Roughness
        Initial roughness [m].
    n_wheels : int
        Wheels per train: a train passage is n_wheels wheel passages.
    settings : GrowthSettings
    checkpoint : path, optional
        File to resume from and to write (atomically) at every save. A checkpoint written for a
        different ``identity``, settings or initial roughness is never reused: on_mismatch = 'error'
        raises, 'restart' discards it and starts afresh.
    identity : dict, optional
        What else the run depends on, JSON-serialisable: rail.chain.grow puts in the scenario, the
        speed and the hash of the physics code (rail.provenance), so that a checkpoint written by
        other code is never resumed.
    progress : file
        Where progress lines go.
    stop_after_updates : int, optional
        Stop early (for tests of the resume path).
    period : float, optional
        The roughness period N L [m], to name the wavelength of a harmonic in a stop message.
    carry : object, optional
        State that train_wear carries from update to update (rail.creepage.coupling.WarmStates, the
        dynamic creepage's periodic u_bar of each wheel), with ``arrays()`` -> {name: ndarray} and
        ``restore(arrays)``: saved in the checkpoint and restored on resume, so that a resumed run
        continues bit for bit as the uninterrupted one (tests/test_growth.py).

    Returns
    -------
    GrowthHistory

    Notes
    -----
    Each update's local error is estimated (step_error) and a value above settings.step_tolerance
    stops the run with GrowthStepError, naming a step that would pass; the wear rate is evaluated
    once more after the last update for this. Force, traction and wear are checked finite where
    they are computed. Where the model's physical assumptions break (contact loss, multiple contact,
    contact lost inside the patch: rail.interaction.ContactLossError, rail.contact.ContactError) the
    run stops: the returned history holds every saved state and the state it stopped at, and its
    ``stopped`` the one-line reason with the passage count and the fastest-growing wavelength (also
    printed to ``progress``). Updates with no stick zone over part of the bay (full slip) are
    reported to ``progress`` and kept in the history.
    """
    train_passages_per_update = settings.passages_per_update / n_wheels
    fp = _fingerprint({"identity": identity, "settings": settings.__dict__,
                       "roughness": hashlib.sha256(np.ascontiguousarray(roughness.Z, dtype=complex).tobytes()).hexdigest()})
    Z = roughness.Z.astype(complex).copy()
    history = GrowthHistory(np.array([0]), Z[None, :].copy())
    done, update = 0, 0
    rate_before = None  # wear per train passage of the last update (for the next update's error estimate)
    ck = Path(checkpoint) if checkpoint else None
    resumed = _resume(ck, fp, on_mismatch, settings.passages, progress, carry) if ck is not None and ck.exists() else None
    if resumed is not None:
        done, Z, update, history, rate_before = resumed

    def same_grid(u1, u2):
        return not settings.vary_grid_spacing or grid_phase(u1) == grid_phase(u2)

    def wear_rate(Z, update):
        """Wear per train passage at roughness Z on the grid of ``update``."""
        dZ, slip = train_wear(Z, grid_phase(update) if settings.vary_grid_spacing else 0.0)
        if slip > 0:
            print(f"warning: no stick zone in the contact over {100 * slip:.1f} % of the bay at {done} passages "
                  "(full slip: saturated creepage or fast unloading; the traction is mu_d p there)", file=progress, flush=True)
        return dZ, slip

    def check(rate_before, rate_after, Z_after, passages_after):
        _check_update(history, settings, train_passages_per_update, ck, rate_before, rate_after, Z_after, passages_after)

    def stop(e, Z):
        """The history up to the state the model broke at, with the reason (see Notes)."""
        nonlocal history
        if done > history.passages[-1]:
            history = GrowthHistory(np.append(history.passages, done), np.vstack([history.Z, Z[None, :]]), history.step_error,
                                    history.full_slip)
        history.step_error = np.append(history.step_error, np.full(len(history.full_slip) - len(history.step_error), np.nan))
        history.stopped = stop_message(done, history.Z[0], Z, e, period)
        print(history.stopped, file=progress, flush=True)
        return history

    t0, done0 = time.perf_counter(), done
    n_updates = 0
    while done < settings.passages:
        try:
            dZ_train, slip = wear_rate(Z, update)
        except (ContactError, ContactLossError) as e:
            return stop(e, Z)
        if rate_before is not None:
            if same_grid(update - 1, update):
                check(rate_before, dZ_train, Z, done)
            else:  # the two rates differ by the grid-tied error too: no estimate from this pair
                history.step_error = np.append(history.step_error, np.nan)
        history.full_slip = np.append(history.full_slip, slip)
        Z = Z - train_passages_per_update * dZ_train
        if not np.all(np.isfinite(Z)):
            raise FloatingPointError(f"the roughness is not finite after {done + settings.passages_per_update} passages.")
        rate_before = dZ_train
        done += settings.passages_per_update
        update += 1
        n_updates += 1
        if done % settings.save_every == 0:
            history = GrowthHistory(np.append(history.passages, done), np.vstack([history.Z, Z[None, :]]), history.step_error, history.full_slip)
            if ck is not None:
                _save_checkpoint(ck, fp, done, Z, history, update, rate_before, carry)
        rate = (done - done0) / max(time.perf_counter() - t0, 1e-9)
        left = (settings.passages - done) / rate if rate > 0 else float("inf")
        print(f"{done} of {settings.passages} passages, {rate:.0f} passages/s, {left:.0f} s left", file=progress, flush=True)
        if stop_after_updates is not None and n_updates >= stop_after_updates:
            return history
    if rate_before is not None:
        try:
            dZ_end, _ = wear_rate(Z, update - 1)  # on the last update's grid, for a clean estimate
        except (ContactError, ContactLossError) as e:
            return stop(e, Z)
        check(rate_before, dZ_end, Z, done)
        print(f"largest estimated update error {100 * np.nanmax(history.step_error):.3g} % of the roughness "
              f"(growth.step_tolerance {100 * settings.step_tolerance:g} %)", file=progress, flush=True)
    return history
