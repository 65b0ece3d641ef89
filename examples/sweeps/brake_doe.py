"""Design of experiments on the braked flywheel: stopping time and peak disc temperature over
the brake force ``fn_max`` and a family of friction tables ``mu_pos`` (scaled copies of one
measured curve). Writes the table (Parquet) and a heat map of the stopping time.

Run: python examples/sweeps/brake_doe.py [--n 15] [--out out/brake_doe]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import stiction as st

HERE = Path(__file__).resolve().parent
BASE_MU = [[0.0, 0.42], [50.0, 0.38], [100.0, 0.35]]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n", type=int, default=15, help="values per axis")
    parser.add_argument("--out", type=Path, default=Path("out/brake_doe"))
    args = parser.parse_args()
    model = st.Model.load(HERE.parent / "braked_flywheel.toml")
    scales = np.linspace(0.6, 1.4, args.n)
    tables = [[[w, round(mu * s, 6)] for w, mu in BASE_MU] for s in scales]
    variants = st.grid({"brake.fn_max": list(np.linspace(1000.0, 3000.0, args.n)), "brake.mu_pos": tables})
    result = st.sweep(model, variants, ["time_of(brake.locked)", "max(disc.T)", "integral(brake.lossPower)"])
    result.table["mu scale"] = [s for _ in range(args.n) for s in scales]
    args.out.mkdir(parents=True, exist_ok=True)
    result.to_parquet(args.out / "brake_doe.parquet")
    ax = result.plot("brake.fn_max", "time_of(brake.locked)", hue="mu scale")
    ax.set_title("stopping time [s]")
    ax.figure.savefig(args.out / "stopping_time.png", dpi=120)
    fastest = result.table.loc[result.table["time_of(brake.locked)"].idxmin()]
    print(
        f"{len(result.table)} variants; fastest stop {fastest['time_of(brake.locked)']:.3f} s "
        f"at fn_max {fastest['brake.fn_max']:.0f} N, mu scale {fastest['mu scale']:.2f} → {args.out}"
    )


if __name__ == "__main__":
    main()
