"""CI figure regression: compare the built figures with the baselines kept under tests/baselines/.

    python tests/regression/figures.py check    # after `snakemake -j2`; exit 1 on any difference
    python tests/regression/figures.py update   # copy results/ into tests/baselines/, on purpose

Data: every plotted variable of results/data/figNN.nc must match the baseline within 1e-3 of the
baseline's largest magnitude (0.05 dB for levels in dB). That is far above the run-to-run noise
(BLAS and platform rounding) and far below any change a reader of the figure could see.
Images: RMS difference at most 5 (of 255) by matplotlib.testing.compare; a failing comparison
leaves a diff image next to the new figure.
The figures are built with the default (full) numerics; nothing is reduced.
"""

from __future__ import annotations

import shutil
import sys
from pathlib import Path

import numpy as np
import xarray as xr

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "results"
BASE = ROOT / "tests" / "baselines"
RTOL = 1e-3
DB_ATOL = 0.05
IMAGE_RMS = 5.0


def compare_data(new: Path, old: Path) -> list[str]:
    problems = []
    with xr.open_dataset(new) as a, xr.open_dataset(old) as b:
        if set(a.data_vars) != set(b.data_vars):
            return [f"{new.name}: variables {sorted(a.data_vars)} differ from the baseline's {sorted(b.data_vars)}"]
        for name in b.data_vars:
            x, y = a[name].values, b[name].values
            if x.shape != y.shape:
                problems.append(f"{new.name}: {name} has shape {x.shape}, baseline {y.shape}")
                continue
            finite = np.isfinite(y)
            if not np.array_equal(finite, np.isfinite(x)):
                problems.append(f"{new.name}: {name} has non-finite values where the baseline has none (or vice versa)")
                continue
            diff = np.abs(x[finite] - y[finite]).max(initial=0.0)
            if "dB" in b[name].attrs.get("units", "") or b[name].attrs.get("level_unit") == "dB":
                limit = DB_ATOL
            else:
                limit = RTOL * np.abs(y[finite]).max(initial=0.0)
            if diff > limit:
                problems.append(f"{new.name}: {name} differs by {diff:.3g} {b[name].attrs.get('units', '')} (allowed {limit:.3g})")
    return problems


def compare_images(new: Path, old: Path) -> list[str]:
    from matplotlib.testing.compare import compare_images as cmp

    result = cmp(str(old), str(new), tol=IMAGE_RMS, in_decorator=True)
    if result is None:
        return []
    return [f"{new.name}: image RMS {result['rms']:.2f} > {IMAGE_RMS} (diff image {result['diff']})"]


def check() -> int:
    problems = []
    for old in sorted((BASE / "data").glob("*.nc")):
        new = RESULTS / "data" / old.name
        problems += compare_data(new, old) if new.exists() else [f"{old.name}: not built"]
    for old in sorted((BASE / "figures").glob("*.png")):
        new = RESULTS / "figures" / old.name
        problems += compare_images(new, old) if new.exists() else [f"{old.name}: not built"]
    n = len(list((BASE / "data").glob("*.nc"))) + len(list((BASE / "figures").glob("*.png")))
    if problems:
        print("figure regression: " + f"{len(problems)} problem(s) in {n} files\n  " + "\n  ".join(problems))
        return 1
    print(f"figure regression: {n} files match their baselines")
    return 0


def update() -> int:
    for sub, pattern in (("data", "fig*.nc"), ("figures", "fig*.png")):
        (BASE / sub).mkdir(parents=True, exist_ok=True)
        for f in sorted((RESULTS / sub).glob(pattern)):
            if f.stem.endswith("-failed-diff"):  # diff images of a failed check are not baselines
                continue
            shutil.copy2(f, BASE / sub / f.name)
    print(f"baselines updated from {RESULTS}")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 2 or sys.argv[1] not in ("check", "update"):
        sys.exit(__doc__)
    sys.exit(check() if sys.argv[1] == "check" else update())
