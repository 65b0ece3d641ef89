"""Monte Carlo of clutch engagement in MSL CoupledClutches: the normal forces and the
friction of the three clutches scatter (±20 %); when does clutch 3 lock? Writes the table
(Parquet) and a histogram of the lock time.

Run: python examples/sweeps/clutch_monte_carlo.py [--n 2000] [--out out/clutch_mc]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

import stiction as st

HERE = Path(__file__).resolve().parent


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n", type=int, default=2000, help="number of variants")
    parser.add_argument("--out", type=Path, default=Path("out/clutch_mc"))
    args = parser.parse_args()
    model = st.Model.load(HERE.parent / "msl" / "CoupledClutches.toml")
    dists = {f"clutch{k}.fn_max": (16.0, 24.0) for k in (1, 2, 3)}
    dists |= {f"clutch{k}.peak": (1.0, 1.3) for k in (1, 2, 3)}
    variants = st.sample(args.n, seed=1, dists=dists)
    result = st.sweep(model, variants, ["time_of(clutch3.locked)", "events()", "max(J4.w)"])
    args.out.mkdir(parents=True, exist_ok=True)
    result.to_parquet(args.out / "clutch_mc.parquet")
    lock = result.table["time_of(clutch3.locked)"].to_numpy()
    locked = lock[~np.isnan(lock)]
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.hist(locked, bins=40)
    ax.set_xlabel("time clutch3 locks [s]")
    ax.set_ylabel("variants")
    fig.savefig(args.out / "lock_time.png", dpi=120)
    print(
        f"{len(lock)} variants; clutch3 locks in {len(locked)}: "
        f"median {np.median(locked):.4f} s, 5–95 % {np.percentile(locked, 5):.4f}–{np.percentile(locked, 95):.4f} s → {args.out}"
    )


if __name__ == "__main__":
    main()
