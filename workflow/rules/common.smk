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


def speed_label(v):
    """Speed in a file name: 40.0 -> '40', 37.5 -> '37.5'."""
    return f"{float(v):g}"


def wheel_offsets():
    """Offsets d between every ordered pair of wheels (0 first): the transfer receptances needed."""
    pos = [float(x) for x in config["wheels"]["positions"]]
    return sorted({0.0} | {round(a - b, 9) for a in pos for b in pos if a != b}, key=abs)


def receptance_tables():
    """Receptance tables of the default track at every configured speed."""
    return expand(
        "results/receptance/default/V{speed}.nc",
        speed=[speed_label(v) for v in config["speeds"]],
    )
