"""Compile the contact marches (rail.kernels.compile_kernels) and list what was compiled."""

from rail.kernels import compile_kernels


def main(which, out_path):
    lines = compile_kernels(tangent_too=(which == "tangent"))
    with open(out_path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(snakemake.wildcards.which, snakemake.output[0])  # noqa: F821
