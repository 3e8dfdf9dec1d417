"""Names of the shared receptance tables, from their content (issue 36).

A receptance table depends on the track, the track numerics and the wheel offsets it holds, and on
nothing else of a scenario. Its folder under results/receptance/ is a short hash of exactly that
content, so adding, removing or renaming a scenario renames no table and reruns no other job, and a
change of the track, its numerics or the wheels gives a table of its own (docs/workflow.md)."""

from __future__ import annotations

import hashlib
import json

__all__ = ["table_key"]


def table_key(track_part: dict, offsets) -> str:
    """Folder name of a receptance table: 10 hex digits of the SHA-256 of its content.

    Parameters
    ----------
    track_part : dict
        ``{"track": <resolved track section>, "numerics": {"track": <resolved numerics.track>}}``.
    offsets : sequence of float
        Wheel offsets d [m] the table holds (their order is irrelevant; rounded to 1 nm).

    Returns
    -------
    str
        e.g. ``'3f9c0a1d2e'``; equal for equal content whatever the scenario's name.
    """
    try:
        d = sorted({round(float(x), 9) + 0.0 for x in offsets})
    except (TypeError, ValueError):
        raise ValueError(f"offsets = {offsets!r} is not allowed: it must be a sequence of numbers in m.") from None
    content = json.dumps({"table": track_part, "offsets": d}, sort_keys=True, default=str)
    return hashlib.sha256(content.encode()).hexdigest()[:10]
