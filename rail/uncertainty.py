"""Uncertainty of the inputs as a seeded ensemble (issue 35; config/uncertainty.yaml).

Each uncertain input is a dotted configuration key with a distribution:

- ``uniform``   (low, high), low <= high
- ``normal``    (mean, std), std >= 0
- ``lognormal`` (median, factor), factor >= 1: log X is normal with mean log(median) and standard
  deviation log(factor), so about 68 % of the draws lie within median / factor .. median x factor
- ``fixed``     (value)

A spread of zero (low = high, std = 0, factor = 1) gives every member the same value exactly.
``contact.friction`` sets both ``contact.friction_static`` and ``contact.friction_dynamic`` (the
default configuration has them equal; a draw keeps them so).

The draws are reproducible bit for bit: numpy's PCG64 generator seeded by SeedSequence(seed).spawn,
one child stream per parameter in the order of the sorted key names, so a parameter's draws depend on
the seed, its own position among the names and the number of members only. Bit for bit holds on one
machine: a lognormal draw goes through numpy's exp and log, which numpy dispatches by CPU feature
(AVX-512 or AVX2 code), so on another CPU it may differ in the last digit (tests compare recorded
draws to a relative tolerance, tests/test_plan.py).
"""

from __future__ import annotations

import copy
import warnings

import numpy as np

__all__ = ["DISTRIBUTIONS", "check_parameters", "sample", "member_config", "band_statistics"]

DISTRIBUTIONS = {"uniform": ("low", "high"), "normal": ("mean", "std"), "lognormal": ("median", "factor"), "fixed": ("value",)}
ALIASES = {"contact.friction": ("contact.friction_static", "contact.friction_dynamic")}


def _number(key, name, value):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
        raise ValueError(f"uncertainty parameter {key}: {name} = {value!r} is not allowed: it must be a finite number.")
    return float(value)


def check_parameters(parameters: dict) -> dict:
    """The parameters' distributions, checked: {key: (distribution, {name: value})}.

    Parameters
    ----------
    parameters : dict
        {dotted key: {distribution: ..., its parameters}} (config/uncertainty.yaml), in the key's unit [SI].

    Returns
    -------
    dict
        The distributions' parameters [the key's SI unit; factor -].

    Raises
    ------
    ValueError
        Naming the key, the value and the valid range.
    """
    if not isinstance(parameters, dict) or not parameters:
        raise ValueError(f"uncertainty parameters = {parameters!r} is not allowed: give {{key: {{distribution: ...}}}}.")
    out = {}
    for key, spec in parameters.items():
        if not isinstance(spec, dict) or spec.get("distribution") not in DISTRIBUTIONS:
            raise ValueError(f"uncertainty parameter {key}: distribution = {spec.get('distribution') if isinstance(spec, dict) else spec!r} "
                             f"is not allowed: it must be one of {', '.join(DISTRIBUTIONS)}.")
        kind = spec["distribution"]
        names = DISTRIBUTIONS[kind]
        extra = sorted(set(spec) - set(names) - {"distribution"})
        if extra or any(n not in spec for n in names):
            raise ValueError(f"uncertainty parameter {key}: a {kind} distribution takes exactly {', '.join(names)} (got {sorted(spec)}).")
        p = {n: _number(key, n, spec[n]) for n in names}
        if kind == "uniform" and not p["low"] <= p["high"]:
            raise ValueError(f"uncertainty parameter {key}: low = {p['low']!r}, high = {p['high']!r} are not allowed: low <= high.")
        if kind == "normal" and p["std"] < 0:
            raise ValueError(f"uncertainty parameter {key}: std = {p['std']!r} is not allowed: it must be >= 0.")
        if kind == "lognormal" and not (p["median"] > 0 and p["factor"] >= 1):
            raise ValueError(f"uncertainty parameter {key}: median = {p['median']!r}, factor = {p['factor']!r} are not allowed: "
                             "median > 0 and factor >= 1.")
        out[key] = (kind, p)
    return out


def sample(parameters: dict, members: int, seed: int) -> dict:
    """Draw the ensemble: {key: (members,) values}, reproducible bit for bit on one machine (module docstring).

    Parameters
    ----------
    parameters : dict
        As check_parameters takes.
    members : int
        Ensemble size [-], >= 1.
    seed : int
        Seed [-], >= 0.

    Returns
    -------
    dict
        {key: ndarray (members,)} in the units of each key.
    """
    if isinstance(members, bool) or not isinstance(members, (int, np.integer)) or members < 1:
        raise ValueError(f"uncertainty members = {members!r} is not allowed: it must be an integer >= 1.")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"uncertainty seed = {seed!r} is not allowed: it must be an integer >= 0.")
    dists = check_parameters(parameters)
    keys = sorted(dists)
    streams = np.random.SeedSequence(int(seed)).spawn(len(keys))
    out = {}
    for key, ss in zip(keys, streams):
        rng = np.random.Generator(np.random.PCG64(ss))
        kind, p = dists[key]
        if kind == "uniform":
            v = p["low"] + (p["high"] - p["low"]) * rng.random(members)
        elif kind == "normal":
            v = p["mean"] + p["std"] * rng.standard_normal(members)
        elif kind == "lognormal":
            v = p["median"] * np.exp(np.log(p["factor"]) * rng.standard_normal(members))
        else:
            v = np.full(members, p["value"])
        out[key] = v
    return {k: out[k] for k in parameters}


def _schema_declares(schema: dict | None, parts) -> bool:
    """Whether the schema's nested ``properties`` declare the dotted key ``parts`` (an optional key)."""
    node = schema
    for p in parts:
        props = node.get("properties") if isinstance(node, dict) else None
        if not isinstance(props, dict) or p not in props:
            return False
        node = props[p]
    return True


def member_config(cfg: dict, values: dict, schema: dict | None = None) -> dict:
    """The configuration of one member: a deep copy of ``cfg`` with each dotted key set to its value
    (``contact.friction`` sets the static and the dynamic friction).

    An optional key that ``cfg`` does not hold (``track.rail.head_height``, ``track.pad.longitudinal_stiffness``,
    ``track.pad.rotational_stiffness``: the schema's defaults apply where they are absent) is set when ``schema``
    declares it; any other key ``cfg`` does not hold is refused (a misspelt key names itself).

    Parameters
    ----------
    cfg : dict
        Resolved configuration.
    values : dict
        {dotted key: value} [the key's SI unit].
    schema : dict, optional
        config/schema/config.schema.yaml: the optional keys it declares may be set although absent.

    Returns
    -------
    dict
        To be validated like any configuration (rail.setup.config).
    """
    out = copy.deepcopy(cfg)
    for key, value in values.items():
        for target in ALIASES.get(key, (key,)):
            *parents, leaf = target.split(".")
            declared = _schema_declares(schema, target.split("."))
            node = out
            for p in parents:
                if not isinstance(node.get(p), dict):
                    if not (declared and p not in node):
                        raise ValueError(f"uncertainty parameter {key}: the configuration has no key {target}.")
                    node[p] = {}
                node = node[p]
            if leaf not in node and not declared:
                raise ValueError(f"uncertainty parameter {key}: the configuration has no key {target}.")
            node[leaf] = float(value)
    return out


def band_statistics(values, interval=(0.1, 0.9)):
    """Median and interval over the members, per band (NaN where a band has no value).

    Parameters
    ----------
    values : ndarray, (members, bands)
        A band quantity of every member (e.g. growth [dB per 100,000 passages]).
    interval : (float, float)
        Quantiles of the interval [-], 0 <= lower < upper <= 1.

    Returns
    -------
    median, lower, upper : ndarray, (bands,)
        In the unit of values.
    """
    lo, hi = (float(q) for q in interval)
    if not 0 <= lo < hi <= 1:
        raise ValueError(f"uncertainty interval = {list(interval)} is not allowed: give quantiles 0 <= lower < upper <= 1.")
    v = np.asarray(values, dtype=float)
    with warnings.catch_warnings():  # a band without any value is NaN by design (no "All-NaN slice" warning)
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanmedian(v, axis=0), np.nanquantile(v, lo, axis=0), np.nanquantile(v, hi, axis=0)
