# Helpers of workflow/rules/characterisation.smk (track characterisation, issue 11). They belong
# in common.smk with the other helpers; they live here until they are moved there.

import re
from pathlib import Path

# The three characterisation results of a track: data results/.../<name>.nc, figure <name>.png.
CHARACTERISATION = ["track_receptance", "moving_receptance", "track_decay_rate"]

def characterised_tracks():
    """Scenarios whose track differs from the default: each track is characterised once, under
    results/tracks/<scenario>/ (the default track under results/data and results/figures)."""
    return [name for name in SCENARIOS if name != "default" and track_name(name) == name]


def characterised_track_pattern():
    """Wildcard constraint for 'track' in the scenario characterisation rules ('default' and
    scenarios on the default track are excluded; never matches if there is no other track)."""
    return "|".join(re.escape(name) for name in characterised_tracks()) or "(?!)"


def characterisation_track(wildcards):
    """Name of the characterised track: the wildcard 'track', 'default' where there is none."""
    return wildcards.get("track", "default")


def characterisation_config(wildcards):
    """Resolved configuration owning the characterised track."""
    return SCENARIOS[characterisation_track(wildcards)]


def characterisation_speeds(wildcards):
    """Speeds (m/s) of the configuration owning the characterised track."""
    return [float(v) for v in characterisation_config(wildcards)["speeds"]]


def measured_decay_rate(wildcards):
    """The scenario's measured.decay_rate CSV, else config/measured/<track>_decay_rate.csv if it
    exists: drawn beside the model's decay rate."""
    file, _ = measured_decay_file(characterisation_config(wildcards), characterisation_track(wildcards))
    return [file] if file else []


def characterisation_targets():
    """Data and figures of every characterisation result of every track in use."""
    default = expand(["results/data/{name}.nc", "results/figures/{name}.png"], name=CHARACTERISATION)
    others = expand(
        "results/tracks/{track}/{name}.{ext}",
        track=characterised_tracks(),
        name=CHARACTERISATION,
        ext=["nc", "png"],
    )
    return default + others
