"""Markdown table for REPORT.md from the JSON lines of measure_rolling_wavy.py (rolling_wavy_results/)."""

import cmath
import json
import math
import sys
from pathlib import Path

RES = Path(__file__).resolve().parent / "rolling_wavy_results"


def load(name):
    p = RES / name
    if not p.exists():
        return {}
    return {json.loads(l)["lam_over_2a"]: json.loads(l) for l in p.read_text().splitlines() if l.strip()}


def cx(v):
    return complex(*v)


def diff(row):
    return cx(row["exact"]["H"]) - cx(row["centred"]["H"])


def fmt(z):
    return f"{z.real:+.3f}{z.imag:+.3f}i"


def polar(z):
    return f"{abs(z):.3f} ∠{math.degrees(cmath.phase(z)):+.0f}°"


def main():
    main_ = load(sys.argv[1] if len(sys.argv) > 1 else "a100_o4.jsonl")
    half = load("a100_o4_half.jsonl")
    a50 = load("a50.jsonl")
    a200 = {**load("a200_o2.jsonl"), **load("a200_o1.jsonl")}
    print("| λ/2a | βa₀ | brute force H (amp ∠ phase) | closed form J0(βa₀) | centred-patch model "
          "| difference (brute − centred) | \\|diff − J0\\| | \\|diff\\| / \\|H\\| | Δ/2: difference | a/h = 50 "
          "| a/h = 200 |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for lo, r in sorted(main_.items()):
        He, Hc, d = cx(r["exact"]["H"]), cx(r["centred"]["H"]), diff(r)
        cols = [f"{lo:g}", f"{r['beta_a0']:.3f}", f"{fmt(He)} ({polar(He)})", f"{r['J0']:+.3f}", fmt(Hc), fmt(d),
                f"{abs(d - r['J0']):.3f}", f"{abs(d) / abs(He):.2f}"]
        for other in (half, a50, a200):
            cols.append(fmt(diff(other[lo])) if lo in other else "–")
        print("| " + " | ".join(cols) + " |")


if __name__ == "__main__":
    main()
