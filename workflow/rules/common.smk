# Helpers that turn the configuration into target lists. Rules live in the other .smk files.

from snakemake.utils import validate

from rail.config import load_yaml, validate_config

# Clear, actionable messages first (key, value, unit, valid range), then snakemake's own
# validation against the same schema.
SCHEMA = load_yaml(workflow.source_path("../../config/schema/config.schema.yaml"))
validate_config(config, SCHEMA, source="configuration (config/config.yaml and --config/--configfile)")
validate(config, "../../config/schema/config.schema.yaml")

# Report figures produced so far, by section of the report.
HALFSPACE_FIGURES = ["02", "03", "04", "05", "06"]


def paper_figures():
    """Every report figure: its picture and its plotted data."""
    return expand(
        ["results/figures/fig{nn}.png", "results/data/fig{nn}.nc"], nn=HALFSPACE_FIGURES
    )
