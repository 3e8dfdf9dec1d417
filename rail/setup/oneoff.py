"""A one-off configuration's own folder (--configfile or --config that changes config/config.yaml):
runs/<name>-<hash of the differing values>/, so that it never writes over the default results."""

from __future__ import annotations

import hashlib
import json
import re
import sys
from pathlib import Path

from .config import load_yaml

__all__ = ["one_off_run_dir"]


def _differing_keys(a, b, prefix=""):
    """Dotted keys whose values differ between two configuration mappings."""
    keys = []
    for k in sorted(set(a) | set(b), key=str):
        x, y = a.get(k), b.get(k)
        if isinstance(x, dict) and isinstance(y, dict):
            keys += _differing_keys(x, y, f"{prefix}{k}.")
        elif x != y:
            keys.append(f"{prefix}{k}")
    return keys


def _value_at(cfg, key):
    """The value under a dotted key of a configuration mapping (None where it is absent)."""
    for part in key.split("."):
        cfg = cfg.get(part) if isinstance(cfg, dict) else None
    return cfg


def one_off_run_dir(config: dict, configfiles, root="."):
    """runs/<name>-<hash> for a configuration that differs from config/config.yaml (a one-off run:
    --configfile my_changes.yaml gives runs/my_changes-<hash>), with runs/<...>/config pointing to
    this project's config/ (so that scenario and input files resolve as here); None for the
    defaults. <hash> is that of the differing keys and their resolved values, so two configurations
    of the same file name get their own folders and one configuration always the same one.
    A one-off run never writes over the default results.

    Parameters
    ----------
    config : dict
        The run's resolved configuration (config/config.yaml with --config/--configfile).
    configfiles : list of str
        The --configfile files given (their names, joined by "_", name the folder).
    root : str or Path
        The project folder.

    Returns
    -------
    Path or None
        The run's folder (made, with its config link), or None for the defaults.
    """
    root = Path(root)
    changed = _differing_keys(config, load_yaml(root / "config/config.yaml"))
    if not changed:
        return None
    stems = [re.sub(r"[^A-Za-z0-9_-]", "_", Path(f).stem) for f in configfiles]
    content = json.dumps({k: _value_at(config, k) for k in changed}, sort_keys=True, default=str)
    digest = hashlib.sha256(content.encode()).hexdigest()[:8]
    name = f"{'_'.join(stems) or 'overrides'}-{digest}"
    run = root / "runs" / name
    run.mkdir(parents=True, exist_ok=True)
    link = run / "config"
    if not link.exists():
        link.symlink_to((root / "config").resolve(), target_is_directory=True)
    print(f"one-off configuration (differs from config/config.yaml in {', '.join(changed[:6])}"
          f"{', ...' if len(changed) > 6 else ''}): it writes under {run}/ and leaves results/ untouched.", file=sys.stderr)
    return run
