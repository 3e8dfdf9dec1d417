"""Perturbation growth per patch transit of every closure value of the closure study."""

import sys

import numpy as np
import xarray as xr

from rail import contact
from rail.setup import build, io


def main(config, values, nodes, out_path, log):
    scn = build.scenario(config)
    m, P, L = scn.material, scn.wheels.static_load, scn.L
    V = float(config["figures"]["wear"]["speed"])
    g = np.zeros((len(values), len(nodes)))
    for i, s in enumerate(values):
        for j, n in enumerate(nodes):
            g[i, j] = contact.perturbation_growth(m, P, V, n, closure="default", closure_scale=s, L=L)
            print(f"s = {s:g}, {n} nodes: growth per transit {g[i, j]:.3f}", file=log, flush=True)
    ds = xr.Dataset(
        {"growth_per_transit": (("closure_scale", "nodes"), g, {"units": "1",
                                                                "long_name": "growth factor per patch transit of a perturbation of "
                                                                             "steady rolling (< 1: well-posed)"})},
        coords={
            "closure_scale": ("closure_scale", np.asarray(values, dtype=float), {"units": "1", "long_name": "closure scale s"}),
            "nodes": ("nodes", np.asarray(nodes), {"units": "1", "long_name": "contact grid nodes across the patch"}),
        },
        attrs={"speed_m_per_s": V, "normal_load_N": P},
    )
    io.write_netcdf(io.finalize(ds, config, title="Well-posedness of the closure family", source="rail.contact.perturbation_growth"), out_path)


if __name__ == "__main__":
    log = open(snakemake.log[0], "w")  # noqa: F821
    sys.stderr = log
    main(snakemake.params.cfg, snakemake.params.values, snakemake.params.nodes, snakemake.output[0], log)  # noqa: F821
