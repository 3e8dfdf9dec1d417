# The linearised growth-rate spectrum (rail/growth_spectrum/, docs/growth-spectrum.md): which
# wavelengths grow and how fast, per speed, from the smooth rail. Named target rate_spectrum (README).
# Its Bloch tables (the spectrum's N-bay period, the scenario's own wheels) are the content-named
# receptance tables of workflow/rules/track.smk (common.smk rate_spectrum_table).


rule rate_spectrum_speed:
    """Growth-rate spectrum of one scenario at one speed (about 30 s CPU at 187 lines with the report's contact, issue 33; tables apart)."""
    input:
        kernels=kernels("tangent"),
        table=rate_spectrum_table,
    output:
        "results/spectrum/{scenario}/V{speed}.nc",
    wildcard_constraints:
        speed="[^_/]+",
        scenario="[^/]+",
    params:
        code=code("rate_spectrum.py"),
        cfg=scenario_config,
        speed=target_speed,
    log:
        "logs/spectrum/{scenario}/V{speed}.log",
    benchmark:
        "benchmarks/spectrum/{scenario}/V{speed}.tsv"
    resources:
        mem_mb=1400,
        runtime=20,
    script:
        "../scripts/rate_spectrum.py"


rule rate_spectrum_map:
    """The spectra of a scenario over its speeds: dataset and speed x wavelength map (one speed: the line alone)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        rate_spectrum_speeds,
    output:
        data="results/spectrum/{scenario}/rate_spectrum.nc",
        figure=report("results/spectrum/{scenario}/rate_spectrum.png", caption="../report/rate_spectrum.rst", category="Growth-rate spectrum",
                      subcategory="{scenario}"),
        summary=report("results/spectrum/{scenario}/summary.md", caption="../report/rate_spectrum.rst", category="Growth-rate spectrum",
                       subcategory="{scenario}"),
        csv=report("results/spectrum/{scenario}/rate_spectrum.csv", caption="../report/rate_spectrum.rst", category="Growth-rate spectrum",
                   subcategory="{scenario}"),
        frequency_map=report("results/spectrum/{scenario}/rate_map.png", caption="../report/rate_spectrum.rst", category="Growth-rate spectrum",
                             subcategory="{scenario}"),
    params:
        code=code("rate_spectrum_map.py"),
    resources:
        mem_mb=300,
        runtime=5,
    log:
        "logs/spectrum/{scenario}/map.log",
    benchmark:
        "benchmarks/spectrum/{scenario}/map.tsv"
    script:
        "../scripts/rate_spectrum_map.py"


rule rate_spectrum:
    """Named target: the growth-rate spectrum of the default scenario over figures.rate_spectrum.speeds."""
    input:
        "results/spectrum/default/rate_spectrum.png",


rule rate_spectrum_sweep:
    """The spectra of a sweep study's points (each at its speed) on the study's grid."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        rate_spectrum_sweep_points,
    output:
        data="results/spectrum_sweeps/{study}.nc",
        figure=report("results/spectrum_sweeps/{study}.png", caption="../report/rate_spectrum_sweep.rst", category="Growth-rate spectrum"),
    params:
        code=code("rate_spectrum_sweep.py"),
        cfg={},  # drawn from the spectra alone, each of which records its configuration
        swept=sweep_keys,
        grid=sweep_values,
        indices=sweep_indices,
        units=sweep_units,
    resources:
        mem_mb=500,
        runtime=5,
    log:
        "logs/spectrum_sweeps/{study}.log",
    benchmark:
        "benchmarks/spectrum_sweeps/{study}.tsv"
    script:
        "../scripts/rate_spectrum_sweep.py"


rule rate_spectrum_sweeps:
    """Named target: the growth-rate spectrum over every sweep study whose swept keys change it
    (not those sweeping only roughness.*: the spectrum is about the smooth rail)."""
    input:
        PLAN.rate_spectrum_sweep_targets(),


rule short_wave:
    """Named target (issue 31): roughness shorter than the contact patch. The growth-rate spectrum of
    the default track with the non-Hertzian normal contact from L / K to 0.6 m at every speed, and the
    broadband study from a limit-like spectrum with both normal-contact models."""
    input:
        PLAN.short_wave_targets(),


rule dynamic_creepage:
    """Named target (issue 43): the growth-rate spectrum at 30 and 50 m/s, 26-75 mm, with the report's
    fixed creepage and with the wheelset's dynamic creepage (rigid spin, trailer in phase and independent,
    motored): the scenario files dyn_*.yaml (docs/dynamic-creepage.md, docs/field.md)."""
    input:
        [f"results/spectrum/{n}/rate_spectrum.png" for n in ("dyn_fixed", "dyn_rigid", "dyn_trailer", "dyn_trailer_independent", "dyn_driven")
         if n in PLAN.scenarios],


rule speed_study:
    """The dynamic-creepage study over speed in one dataset, figure and table: per mechanism, track and speed
    the fastest line and its frequency, the line nearest the pinned-pinned frequency, and whether the
    growing band keeps its frequency or its wavelength (rail.studies.speed_study)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        spectra=[f for files in PLAN.speed_study_spectra().values() for f in files],
    output:
        data="results/dynamic_creepage/speeds.nc",
        figure=report("results/dynamic_creepage/speeds.png", caption="../report/speed_study.rst", category="Dynamic creepage"),
        table=report("results/dynamic_creepage/speeds.md", caption="../report/speed_study.rst", category="Dynamic creepage"),
    params:
        code=code("speed_study.py"),
        cfg={n: SCENARIOS[n] for n in PLAN.speed_study_spectra()},
        spectra=PLAN.speed_study_spectra(),
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/dynamic_creepage/speeds.log",
    benchmark:
        "benchmarks/dynamic_creepage/speeds.tsv"
    script:
        "../scripts/speed_study.py"


rule dynamic_creepage_speeds:
    """Named target (issue 43): the growth-rate spectrum at 20, 40, 60 and 80 m/s, 20-120 mm, on the default
    and a stiff-pad (1e9 N/m) track, with the report's fixed creepage, the trailer and the motored wheelsets'
    torsion, the rail's longitudinal flexibility, friction falling with slip, and all of them together: the scenario files
    dynspeed_*.yaml (docs/dynamic-creepage.md), each scenario's map, and the study's summary (rule speed_study)."""
    input:
        [f"results/spectrum/{n}/rate_spectrum.png" for n in PLAN.speed_study_spectra()],
        "results/dynamic_creepage/speeds.png",


rule rail_flexibility:
    """Named target (issue 43): the growth-rate spectrum at 30, 40 and 50 m/s, 24-100 mm, with the rail's
    longitudinal flexibility at the contact, alone and with the trailer and the motored wheelset: the
    scenario files dyn_rail*.yaml (docs/dynamic-creepage.md, docs/field.md)."""
    input:
        PLAN.rail_flexibility_targets(),
