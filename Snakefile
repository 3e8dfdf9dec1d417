# railgrowth: rail roughness growth on tangent track (Sheng, Thompson & Jones).
# `snakemake -j2` builds every report figure; studies are named targets (docs/workflow.md).
# `snakemake --report report.html` writes the HTML report of whatever is built (rule report_all).

import os
import sys

from snakemake.utils import min_version

from rail.setup.runtime import check_file_size_limit, one_blas_thread, reporting_only

# One BLAS/OpenMP thread per job unless the caller's environment says otherwise (why: its docstring);
# before the first include imports numpy. Jobs inherit this process's environment.
one_blas_thread(os.environ)
check_file_size_limit(workflow.basedir)  # a `ulimit -f` below a rule file: named here, not by Snakemake's source cache

min_version("9.0")


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"


# A one-off configuration (--configfile or --config that changes config/config.yaml) writes under its
# own folder, runs/<name>-<hash of the differing values>/ (results, logs, report), and never over
# the default results.
ONE_OFF = one_off_run_dir(config, workflow.overwrite_configfiles)
if ONE_OFF is not None:
    workflow.workdir(str(ONE_OFF))


include: "workflow/rules/kernels.smk"
include: "workflow/rules/halfspace.smk"
include: "workflow/rules/track.smk"
include: "workflow/rules/forces.smk"
include: "workflow/rules/wear.smk"
include: "workflow/rules/growth.smk"
include: "workflow/rules/spectrum.smk"
include: "workflow/rules/sweeps.smk"
include: "workflow/rules/characterisation.smk"
include: "workflow/rules/closure.smk"
include: "workflow/rules/studies.smk"
include: "workflow/rules/irregular.smk"
include: "workflow/rules/fleet.smk"
include: "workflow/rules/noise.smk"
include: "workflow/rules/mitigation.smk"


# `snakemake --report report.html` (without a target) reports what is built: report_all is then the
# default target. With --report-after-run the run itself builds the figure set as usual.
REPORTING = reporting_only(sys.argv)


rule all:
    default_target: not REPORTING
    input:
        PLAN.paper_figures(),


rule report_all:
    """The HTML report of whatever is built, and only that: the report figures that exist and every
    output of every study that exists (a user's study alone is enough). snakemake --report report.html
    (report_all is the default target of --report); nothing is computed."""
    default_target: REPORTING
    input:
        built_paper_figures(),
        built_studies(),
