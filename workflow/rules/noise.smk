from rail.setup.inputs import fleet_noise_growth_file


# Rolling noise over traffic (CNOSSOS-EU) and grinding by noise, issue 56 (docs/noise.md).


rule growth_noise:
    """Rolling noise by CNOSSOS-EU at every save of a one-train growth run, its change since the
    start, the cycle average and the band rms, and when each noise criterion of figures.noise trips
    (rail.studies.noise; the API's rail.app.api.noise and `railgrowth noise` alike)."""
    localrule: True
    input:
        "results/growth/{scenario}/V{speed}.nc",
        band_limit_file,
    output:
        data="results/growth/{scenario}/V{speed}_noise.nc",
        csv=report("results/growth/{scenario}/V{speed}_noise.csv", caption="../report/growth_noise.rst", category="Rolling noise (CNOSSOS-EU)",
                   subcategory="{scenario}"),
        figure=report("results/growth/{scenario}/V{speed}_noise.png", caption="../report/growth_noise.rst", category="Rolling noise (CNOSSOS-EU)",
                      subcategory="{scenario}"),
    priority: PRIORITY_KERNELS  # a cheap view: not queued behind long jobs (issue 45, item 14)
    params:
        code=code("noise.py"),
        cfg=scenario_config,
    resources:
        mem_mb=400,
        runtime=15,
    log:
        "logs/growth/{scenario}/V{speed}_noise.log",
    benchmark:
        "benchmarks/growth/{scenario}/V{speed}_noise.tsv"
    script:
        "../scripts/noise.py"


rule noise:
    """Named target: the noise over traffic of the default growth runs at every configured speed and
    of the scenarios with a roughness period of N > 1 bays (the runs of the named target bands), each
    whose noise can be computed (rail.setup.inputs.noise_problem)."""
    input:
        PLAN.noise_targets(),


rule fleet_noise:
    """Rolling noise by CNOSSOS-EU at every save of a fleet's growth run: one traffic class per
    (vehicle, speed) of the fleet, the line's sound power per metre their energy sum, per class and
    total, and when each noise criterion of figures.noise trips on the total (rail.studies.noise; the
    script, API and `railgrowth noise` of the one-train noise alike)."""
    localrule: True
    input:
        lambda wc: fleet_noise_growth_file(wc.scenario, PLAN.fleet_classes, SCENARIOS.get(wc.scenario)),
        band_limit_file,
    output:
        data="results/fleet/{scenario}/growth_noise.nc",
        csv=report("results/fleet/{scenario}/growth_noise.csv", caption="../report/fleet_noise.rst", category="Traffic (fleet)",
                   subcategory="{scenario}"),
        figure=report("results/fleet/{scenario}/growth_noise.png", caption="../report/fleet_noise.rst", category="Traffic (fleet)",
                      subcategory="{scenario}"),
    priority: PRIORITY_KERNELS  # a cheap view: not queued behind long jobs (issue 45, item 14)
    params:
        code=code("noise.py"),
        cfg=scenario_config,
    resources:
        mem_mb=400,
        runtime=15,
    log:
        "logs/fleet/{scenario}/growth_noise.log",
    benchmark:
        "benchmarks/fleet/{scenario}/growth_noise.tsv"
    script:
        "../scripts/noise.py"
