# Track characterisation (issue 11): point receptance, moving-load receptance at the contact
# point and vertical track decay rate of each track in use, to check the track model against
# site measurements. Each job needs only the track: no contact, wear or growth job runs.
# The default track's results go to results/data and results/figures; a scenario whose track
# differs from the default gets its own under results/tracks/<scenario>/.


rule track_receptance:
    """Point receptance above a sleeper and at mid-span, with the characteristic frequencies."""
    output:
        data="results/data/track_receptance.nc",
        figure=report(
            "results/figures/track_receptance.png",
            caption="../report/track_receptance.rst",
            category="Track characterisation",
            subcategory="default",
        ),
    params:
        code=code("track_receptance.py"),
        cfg=characterisation_config,
        name=characterisation_track,
    log:
        "logs/characterisation/default/track_receptance.log",
    benchmark:
        "benchmarks/characterisation/default/track_receptance.tsv"
    resources:
        mem_mb=900,
        runtime=10,
    script:
        "../scripts/track_receptance.py"


use rule track_receptance as track_receptance_scenario with:
    output:
        data="results/tracks/{track}/track_receptance.nc",
        figure=report(
            "results/tracks/{track}/track_receptance.png",
            caption="../report/track_receptance.rst",
            category="Track characterisation",
            subcategory="{track}",
        ),
    wildcard_constraints:
        track=PLAN.characterised_track_pattern(),
    log:
        "logs/characterisation/{track}/track_receptance.log",
    benchmark:
        "benchmarks/characterisation/{track}/track_receptance.tsv"


rule moving_receptance:
    """Moving-load receptance a_0 at the contact point per speed, beside the stationary bay average."""
    output:
        data="results/data/moving_receptance.nc",
        figure=report(
            "results/figures/moving_receptance.png",
            caption="../report/track_moving_receptance.rst",
            category="Track characterisation",
            subcategory="default",
        ),
    params:
        code=code("moving_receptance.py"),
        cfg=characterisation_config,
        name=characterisation_track,
        speeds=characterisation_speeds,
    log:
        "logs/characterisation/default/moving_receptance.log",
    benchmark:
        "benchmarks/characterisation/default/moving_receptance.tsv"
    resources:
        mem_mb=900,
        runtime=15,
    script:
        "../scripts/moving_receptance.py"


use rule moving_receptance as moving_receptance_scenario with:
    output:
        data="results/tracks/{track}/moving_receptance.nc",
        figure=report(
            "results/tracks/{track}/moving_receptance.png",
            caption="../report/track_moving_receptance.rst",
            category="Track characterisation",
            subcategory="{track}",
        ),
    wildcard_constraints:
        track=PLAN.characterised_track_pattern(),
    log:
        "logs/characterisation/{track}/moving_receptance.log",
    benchmark:
        "benchmarks/characterisation/{track}/moving_receptance.tsv"


rule track_decay_rate:
    """Vertical track decay rate in one-third-octave bands (EN 15461), with a measured one if given."""
    input:
        measured_decay_rate,
    output:
        data="results/data/track_decay_rate.nc",
        figure=report(
            "results/figures/track_decay_rate.png",
            caption="../report/track_decay_rate.rst",
            category="Track characterisation",
            subcategory="default",
        ),
    params:
        code=code("track_decay_rate.py"),
        cfg=characterisation_config,
        name=characterisation_track,
    log:
        "logs/characterisation/default/track_decay_rate.log",
    benchmark:
        "benchmarks/characterisation/default/track_decay_rate.tsv"
    resources:
        mem_mb=900,
        runtime=20,
    script:
        "../scripts/track_decay_rate.py"


use rule track_decay_rate as track_decay_rate_scenario with:
    output:
        data="results/tracks/{track}/track_decay_rate.nc",
        figure=report(
            "results/tracks/{track}/track_decay_rate.png",
            caption="../report/track_decay_rate.rst",
            category="Track characterisation",
            subcategory="{track}",
        ),
    wildcard_constraints:
        track=PLAN.characterised_track_pattern(),
    log:
        "logs/characterisation/{track}/track_decay_rate.log",
    benchmark:
        "benchmarks/characterisation/{track}/track_decay_rate.tsv"


rule track_characterisation:
    """Named target: receptance, moving-load receptance and decay rate of every track in use."""
    input:
        PLAN.characterisation_targets(),
