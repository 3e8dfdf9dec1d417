# Section 5: roughness growth over many passages (Figs 20, 21, 23-27).


rule growth:
    """Roughness growth of one scenario at one speed from its initial roughness."""
    input:
        kernels=kernels("march"),
        table=growth_table,
        roughness=roughness_file,
    output:
        "results/growth/{scenario}/V{speed}.nc",
    priority: growth_priority
    params:
        code=code("growth.py"),
        cfg=physics_config,
        speed=target_speed,
        checkpoint="results/checkpoints/{scenario}_V{speed}.npz",
    log:
        "logs/growth/{scenario}/V{speed}.log",
    benchmark:
        "benchmarks/growth/{scenario}/V{speed}.tsv"
    resources:
        mem_mb=lambda w: cell_memory_mb(PLAN.objects[w.scenario], 1600, 2.0),
        runtime=growth_runtime,
    script:
        "../scripts/growth.py"


rule growth_3d:
    """The three-dimensional plot of section 5: level over passages and wavenumber (the default
    scenario, as the report draws it) or wavelength (log, mm; any other scenario)."""
    localrule: True
    input:
        "results/growth/{scenario}/V{speed}.nc",
    output:
        report("results/growth/{scenario}/V{speed}_3d.png", caption="../report/growth_3d.rst", category="Section 5: roughness growth",
               subcategory="{scenario}"),
    priority: PRIORITY_KERNELS  # a cheap view: not queued behind long jobs (issue 45, item 14)
    params:
        code=code("growth_figure.py"),
        axis=growth_3d_axis,
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/growth/{scenario}/V{speed}_3d.log",
    benchmark:
        "benchmarks/growth/{scenario}/V{speed}_3d.tsv"
    script:
        "../scripts/growth_figure.py"


rule growth_narrowband:
    """Growth over a roughness period of N bays: narrow-band spectrum beside the one-bay comb, and
    the profiles over the N bays."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        "results/growth/{scenario}/V{speed}.nc",
    output:
        report("results/growth/{scenario}/V{speed}_narrowband.png", caption="../report/growth_narrowband.rst",
               category="Roughness at any wavelength"),
    params:
        code=code("growth_figure.py"),
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/growth/{scenario}/V{speed}_narrowband.log",
    benchmark:
        "benchmarks/growth/{scenario}/V{speed}_narrowband.tsv"
    script:
        "../scripts/growth_figure.py"


rule scenario_overview:
    """Any scenario's growth run on one page, every saved passage count: narrow-band spectrum against
    wavelength beside the default's (or a note why there is none), the change in level, profiles and
    the contact force along the period."""
    localrule: True
    input:
        unpack(scenario_overview_inputs),
    output:
        report("results/growth/{scenario}/V{speed}_overview.png", caption="../report/scenario_overview.rst",
               category="Scenarios", subcategory="{scenario}"),
    priority: PRIORITY_KERNELS  # a cheap view: not queued behind long jobs (issue 45, item 14)
    params:
        code=code("growth_figure.py"),
        default_note=scenario_overview_note,
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/growth/{scenario}/V{speed}_overview.log",
    benchmark:
        "benchmarks/growth/{scenario}/V{speed}_overview.tsv"
    script:
        "../scripts/growth_figure.py"


for _study_name in PLAN.study_names() + sorted(PLAN.broken):

    rule:
        name:
            f"study_{_study_name}"
        input:
            PLAN.study_input(_study_name),


rule growth_bands:
    """One-third-octave band levels of a growth run at every saved passage count, growth per band,
    the grinding interval against the limit spectrum; CSV exports of the bands, the narrow-band levels
    and the roughness for rolling-noise tools (docs/exports.md)."""
    localrule: True
    input:
        "results/growth/{scenario}/V{speed}.nc",
        band_limit_file,
    output:
        data="results/growth/{scenario}/V{speed}_bands.nc",
        csv=report("results/growth/{scenario}/V{speed}_bands.csv", caption="../report/growth_bands.rst", category="Roughness bands (EN 15610 form)",
                   subcategory="{scenario}"),
        narrow_csv=report("results/growth/{scenario}/V{speed}_narrowband.csv", caption="../report/growth_bands.rst",
                          category="Roughness bands (EN 15610 form)",
                          subcategory="{scenario}"),
        rolling_noise_csv=report("results/growth/{scenario}/V{speed}_rolling_noise_roughness.csv", caption="../report/growth_bands.rst",
                                 category="Roughness bands (EN 15610 form)", subcategory="{scenario}"),
        figure=report("results/growth/{scenario}/V{speed}_bands.png", caption="../report/growth_bands.rst",
                      category="Roughness bands (EN 15610 form)",
                      subcategory="{scenario}"),
    priority: PRIORITY_KERNELS  # a cheap view: not queued behind long jobs (issue 45, item 14)
    params:
        code=code("growth_bands.py"),
        cfg=scenario_config,
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/growth/{scenario}/V{speed}_bands.log",
    benchmark:
        "benchmarks/growth/{scenario}/V{speed}_bands.tsv"
    script:
        "../scripts/growth_bands.py"


rule bands:
    """Named target: the band view of the default growth runs and of the scenarios with a
    roughness period of N > 1 bays."""
    input:
        PLAN.band_targets(),


rule any_wavelength:
    """Named target: every scenario whose roughness is periodic over N > 1 bays (narrow-band figures)
    and every such sweep (ensembles)."""
    input:
        PLAN.any_wavelength_targets(),


rule growth_figures:
    """Figs 20, 21, 23-27 from the growth runs, in one job (a job's start-up, 3 s CPU, is several
    times the drawing of one figure)."""
    priority: PRIORITY_KERNELS  # a short drawing or summing job: not queued behind long jobs (issue 57)
    localrule: True
    input:
        # evaluated only when the figures are planned: the scenarios they name may be absent otherwise
        lambda w: PLAN.growth_figures_runs(),
    output:
        data=expand("results/data/fig{nn}.nc", nn=GROWTH_FIGURES),
        figure=[
            report(f"results/figures/fig{nn}.png", caption=f"../report/fig{nn}.rst", category="Section 5: roughness growth")
            for nn in GROWTH_FIGURES
        ],
    params:
        code=code("growth_figure.py"),
        runs=lambda w: PLAN.growth_figures_labelled(),
        cfg=config_part(GROWTH_FIGURE_KEYS),
    resources:
        mem_mb=400,
        runtime=5,
    log:
        "logs/figures/growth_figures.log",
    benchmark:
        "benchmarks/figures/growth_figures.tsv"
    script:
        "../scripts/growth_figure.py"
