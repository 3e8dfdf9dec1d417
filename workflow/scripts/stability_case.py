"""One case of the stability suite (rail.studies.stability.run_case); the outcome is written, never raised."""

import json
import sys

from rail.setup.config import load_yaml
from rail.studies import stability


def main(config, schema_path, name, case, out_path, log):
    rec = stability.run_case(config, load_yaml(schema_path), name, case)
    print(json.dumps(rec, indent=1), file=log)
    with open(out_path, "w") as f:
        json.dump(rec, f, indent=1)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    main(snakemake.params.cfg, "config/schema/config.schema.yaml", snakemake.wildcards.case, snakemake.params.case, snakemake.output[0], log)  # noqa: F821
