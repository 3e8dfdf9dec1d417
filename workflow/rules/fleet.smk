# Traffic as a fleet (issue 35, docs/traffic.md): growth and the growth-rate spectrum of a scenario with
# `fleet:`. One receptance table per (track, speed), with the offsets of every vehicle of every fleet
# on the track, serves every vehicle and every fleet scenario at that speed (computed once).


rule fleet_receptance:
    """Receptance table a_{p-k}(k Omega_0, d) of a track at one fleet class speed, with the offsets of
    every axle pair of every fleet vehicle on the track (rail.chain.fleet_tables)."""
    output:
        "results/receptance/{track}/fleet_V{speed}.nc",
    wildcard_constraints:
        speed="[^_/]+",
    params:
        code=code("receptance.py"),
        cfg=fleet_track_config,
        offsets=fleet_offsets,
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
        speeds=fleet_table_speeds,
        checkpoint="results/checkpoints/{scenario}_fleet.npz",
    log:
        "logs/fleet/{scenario}/growth.log",
    benchmark:
        "benchmarks/fleet/{scenario}/growth.tsv"
    resources:
        mem_mb=1000,
        runtime=fleet_growth_runtime,
    script:
        "../scripts/fleet_growth.py"


rule fleet_rate_spectrum:
    """Growth-rate spectrum under a scenario's fleet: the traffic-weighted rate per wavelength, each
    class's contribution kept (rail.growth_spectrum.fleet_rate_spectrum), per fleet passage and per year."""
    input:
        kernels=kernels("tangent"),
        tables=fleet_spectrum_tables,
    output:
        data="results/fleet/{scenario}/rate_spectrum.nc",
        figure=report("results/fleet/{scenario}/rate_spectrum.png", caption="../report/fleet_rate_spectrum.rst", category="Traffic (fleet)"),
    params:
        code=code("fleet_rate_spectrum.py"),
        cfg=scenario_config,
        speeds=fleet_table_speeds,
    log:
        "logs/fleet/{scenario}/rate_spectrum.log",
    benchmark:
        "benchmarks/fleet/{scenario}/rate_spectrum.tsv"
    resources:
        mem_mb=1400,
        runtime=60,
    script:
        "../scripts/fleet_rate_spectrum.py"


rule traffic_study_summary:
    """The traffic study's cases side by side: growth-rate spectrum per case, one-third-octave band rates,
    what the pinned-pinned and the fastest-growing bands do across the spreads and drives."""
    input:
        traffic_study_inputs,
    output:
        data="results/traffic_study/traffic_study.nc",
        figure=report("results/traffic_study/spectra.png", caption="../report/traffic_study.rst", category="Traffic (fleet)"),
        summary="results/traffic_study/summary.md",
    params:
        code=code("traffic_study.py"),
        cfg={},  # drawn from the spectra alone, each of which records its configuration
        cases=traffic_study_cases,
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
