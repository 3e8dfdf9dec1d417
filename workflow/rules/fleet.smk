# Traffic as a fleet (issue 35, docs/traffic.md): growth and the growth-rate spectrum of a scenario with
# `fleet:`. One receptance table per class speed, named by its content (the track, its numerics and the
# offsets of the fleet's vehicles), serves every vehicle of the fleet and every fleet scenario of the
# same vehicles on that track (computed once).


rule fleet_receptance:
    """Receptance table a_{p-k}(k Omega_0, d) of a track at one fleet class speed, with the offsets of
    every axle pair of the fleet's vehicles (rail.chain.fleet_tables)."""
    output:
        "results/receptance/{track}/fleet_V{speed}.nc",
    wildcard_constraints:
        speed="[^_/]+",
    params:
        code=code("receptance.py"),
        cfg=fleet_track_config,
        offsets=fleet_offsets,
        speed=fleet_table_speed,
        bays=table_bays,
    message:
        "fleet receptance table: track {wildcards.track}, V = {wildcards.speed} m/s, offsets {params.offsets} m"
    log:
        "logs/receptance/{track}/fleet_V{speed}.log",
    benchmark:
        "benchmarks/receptance/{track}/fleet_V{speed}.tsv"
    resources:
        mem_mb=1200,
        runtime=10,
    script:
        "../scripts/receptance.py"


use rule fleet_receptance as fleet_receptance_bloch with:
    output:
        "results/receptance/{track}/fleet_V{speed}_N{bays}.nc",
    wildcard_constraints:
        speed="[^_/]+",
        bays="[0-9]+",
    message:
        "fleet receptance tables: track {wildcards.track}, V = {wildcards.speed} m/s, N = {wildcards.bays} bays, offsets {params.offsets} m"
    log:
        "logs/receptance/{track}/fleet_V{speed}_N{bays}.log",
    benchmark:
        "benchmarks/receptance/{track}/fleet_V{speed}_N{bays}.tsv"
    resources:
        mem_mb=1200,
        runtime=30,


rule fleet_growth:
    """Roughness growth under a scenario's fleet: each update applies the traffic-weighted wear of every
    (vehicle, speed) class (rail.chain.grow_fleet), resumable from its checkpoint."""
    input:
        kernels=kernels("march"),
        tables=fleet_growth_tables,
        roughness=roughness_file,
    output:
        "results/fleet/{scenario}/growth.nc",
    params:
        code=code("fleet_growth.py"),
        cfg=physics_config,
        speeds=lambda w: PLAN.fleet_speeds(w.scenario),
        checkpoint="results/checkpoints/{scenario}_fleet.npz",
    log:
        "logs/fleet/{scenario}/growth.log",
    benchmark:
        "benchmarks/fleet/{scenario}/growth.tsv"
    resources:
        mem_mb=1000,
        runtime=growth_runtime,
    script:
        "../scripts/fleet_growth.py"


rule fleet_class_spectrum:
    """Growth-rate spectrum of one (vehicle, speed) class of a fleet, per passage of its train
    (rail.growth_spectrum.rate_spectrum): a job of its own, shared by every fleet holding the class,
    named <vehicle>_V<speed>_<hash of its content> (rail.setup.study_files.class_key)."""
    input:
        kernels=kernels("tangent"),
        table=fleet_class_table,
    output:
        "results/fleet/classes/{key}.npz",
    wildcard_constraints:
        key="[A-Za-z0-9.-]+_V[0-9.e+-]+_[0-9a-f]{16}",
    params:
        code=code("fleet_class_spectrum.py"),
        cfg=fleet_class_config,
        job=fleet_class_params,
        label=lambda w: PLAN.fleet_class_label(w.key),
    message:
        "fleet class spectrum {wildcards.key}: {params.label}"
    log:
        "logs/fleet/classes/{key}.log",
    benchmark:
        "benchmarks/fleet/classes/{key}.tsv"
    resources:
        mem_mb=lambda w: PLAN.fleet_class_resources(w.key)["mem_mb"],  # from its lines and axles: 2.3 GB at the fleet defaults (docs/traffic.md)
        runtime=lambda w: PLAN.fleet_class_resources(w.key)["runtime"],
    script:
        "../scripts/fleet_class_spectrum.py"


rule fleet_rate_spectrum:
    """Growth-rate spectrum under a scenario's fleet: the traffic-weighted rate per wavelength, each
    class's contribution kept (rail.growth_spectrum.fleet_spectrum_of), per fleet passage and per year."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    input:
        fleet_class_spectra,
    output:
        data="results/fleet/{scenario}/rate_spectrum.nc",
        figure=report("results/fleet/{scenario}/rate_spectrum.png", caption="../report/fleet_rate_spectrum.rst", category="Traffic (fleet)"),
    params:
        code=code("fleet_rate_spectrum.py"),
        cfg=scenario_config,
    log:
        "logs/fleet/{scenario}/rate_spectrum.log",
    benchmark:
        "benchmarks/fleet/{scenario}/rate_spectrum.tsv"
    resources:
        mem_mb=500,
        runtime=5,
    script:
        "../scripts/fleet_rate_spectrum.py"


rule fleet_settled_spectrum:
    """The expected rail roughness under a fleet's wheels' roughness (wheel_source per vehicle, issue 58): per fleet
    passage S_{n+1} = a S_n + Q, a = sum_c w_c abs(1 - R_c)^2, Q = sum_c w_c Q_c; the level each band settles to and
    the time from a ground rail to the limit, from the fleet's spectrum (which carries the source)."""
    priority: PRIORITY_KERNELS  # a short drawing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        "results/fleet/{scenario}/rate_spectrum.nc",
    output:
        figure=report("results/fleet/{scenario}/settled.png", caption="../report/settled_spectrum.rst", category="Wheels' roughness",
                      subcategory="{scenario}"),
        csv=report("results/fleet/{scenario}/settled.csv", caption="../report/settled_spectrum.rst", category="Wheels' roughness",
                   subcategory="{scenario}"),
        summary=report("results/fleet/{scenario}/settled.md", caption="../report/settled_spectrum.rst", category="Wheels' roughness",
                       subcategory="{scenario}"),
    params:
        code=code("settled_spectrum.py"),
    resources:
        mem_mb=300,
        runtime=5,
    log:
        "logs/fleet/{scenario}/settled.log",
    benchmark:
        "benchmarks/fleet/{scenario}/settled.tsv"
    script:
        "../scripts/settled_spectrum.py"


rule traffic_study_summary:
    """The traffic study's cases side by side: growth-rate spectrum per case, one-third-octave band rates,
    what the pinned-pinned and the fastest-growing bands do across the spreads and drives."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        PLAN.traffic_study_inputs(),
    output:
        data="results/traffic_study/traffic_study.nc",
        figure=report("results/traffic_study/spectra.png", caption="../report/traffic_study.rst", category="Traffic (fleet)"),
        summary="results/traffic_study/summary.md",
    params:
        code=code("traffic_study.py"),
        cfg={},  # drawn from the spectra alone, each of which records its configuration
        cases=PLAN.traffic_study_labels(),
    log:
        "logs/traffic_study/summary.log",
    benchmark:
        "benchmarks/traffic_study/summary.tsv"
    resources:
        mem_mb=500,
        runtime=5,
    script:
        "../scripts/traffic_study.py"


rule traffic_study:
    """Named target (issue 35): the report's 40 m/s case under a locomotive and coach mix at speed spreads
    of 0, 5, 10 and 20 %, locomotive driven or braked (config/traffic_study.yaml, README "Traffic")."""
    input:
        "results/traffic_study/spectra.png",
        "results/traffic_study/summary.md",


rule uncertainty_member:
    """Growth-rate spectrum of one member of the uncertainty ensemble (config/uncertainty.yaml): the default
    configuration with the member's drawn friction, wear coefficient, creepage and pad stiffness; its own
    receptance tables (the pad stiffness differs per member)."""
    input:
        kernels=kernels("tangent"),
    output:
        "results/uncertainty/members/m{member}.nc",
    wildcard_constraints:
        member="[0-9]+",
    params:
        code=code("uncertainty_member.py"),
        cfg=uncertainty_member_config,
        speed=PLAN.uncertainty.get("speed"),
    log:
        "logs/uncertainty/m{member}.log",
    benchmark:
        "benchmarks/uncertainty/m{member}.tsv"
    resources:
        mem_mb=1200,  # measured: max_rss 315 MB, 409 MB the run's largest process (16 members), x 1.5 + 500
        runtime=30,
    script:
        "../scripts/uncertainty_member.py"


rule uncertainty_ensemble:
    """The ensemble's band spectrum: per one-third-octave band, the median over the members and the stated interval."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        PLAN.uncertainty_members(),
    output:
        data="results/uncertainty/ensemble.nc",
        figure=report("results/uncertainty/band_interval.png", caption="../report/uncertainty.rst", category="Traffic (fleet)"),
    params:
        code=code("uncertainty_ensemble.py"),
        cfg={},  # drawn from the members alone, each of which records its configuration
        draws=PLAN.uncertainty.get("draws"),
        interval=PLAN.uncertainty.get("interval"),
    log:
        "logs/uncertainty/ensemble.log",
    benchmark:
        "benchmarks/uncertainty/ensemble.tsv"
    resources:
        mem_mb=300,
        runtime=5,
    script:
        "../scripts/uncertainty_ensemble.py"


rule uncertainty:
    """Named target (issue 35): the growth-rate band spectrum with the uncertainty of the inputs (config/uncertainty.yaml)."""
    input:
        "results/uncertainty/band_interval.png",


rule fleet_bands:
    """One-third-octave band view of a fleet's growth run, as of a one-train run (script growth_bands.py,
    rail.studies.exports.band_outputs): band levels, growth per band, the grinding interval in axle
    passages, years and MGT of the fleet's traffic, the band, narrow-band and rolling-noise CSV exports."""
    localrule: True
    input:
        "results/fleet/{scenario}/growth.nc",
        band_limit_file,
    output:
        data="results/fleet/{scenario}/bands.nc",
        csv=report("results/fleet/{scenario}/bands.csv", caption="../report/fleet_bands.rst", category="Traffic (fleet)", subcategory="{scenario}"),
        narrow_csv=report("results/fleet/{scenario}/narrowband.csv", caption="../report/fleet_bands.rst", category="Traffic (fleet)",
                          subcategory="{scenario}"),
        rolling_noise_csv=report("results/fleet/{scenario}/rolling_noise_roughness.csv", caption="../report/fleet_bands.rst",
                                 category="Traffic (fleet)", subcategory="{scenario}"),
        figure=report("results/fleet/{scenario}/bands.png", caption="../report/fleet_bands.rst",
                      category="Traffic (fleet)", subcategory="{scenario}"),
    priority: PRIORITY_KERNELS  # a cheap view: not queued behind long jobs (issue 45, item 14)
    params:
        code=code("growth_bands.py"),
        cfg=scenario_config,
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/fleet/{scenario}/bands.log",
    benchmark:
        "benchmarks/fleet/{scenario}/bands.tsv"
    script:
        "../scripts/growth_bands.py"


rule fleet_overview:
    """A fleet's growth run on one page (as scenario_overview): narrow-band spectrum, change in level,
    profiles and contact force along the period; no one-train default to compare with."""
    localrule: True
    input:
        run="results/fleet/{scenario}/growth.nc",
    output:
        report("results/fleet/{scenario}/overview.png", caption="../report/fleet_overview.rst", category="Traffic (fleet)", subcategory="{scenario}"),
    priority: PRIORITY_KERNELS
    params:
        code=code("growth_figure.py"),
        default_note="a fleet: no one-train default run to compare with",
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/fleet/{scenario}/overview.log",
    benchmark:
        "benchmarks/fleet/{scenario}/overview.tsv"
    script:
        "../scripts/growth_figure.py"
