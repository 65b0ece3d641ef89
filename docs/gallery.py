"""The gallery and the tutorial's output, made by running the examples at documentation build.

Each model file in examples/ and examples/msl/ is simulated with its own experiment and its
main signals plotted; examples/vehicle_launch.py (the tutorial's model) and
examples/vehicle_stop.py (a brake test's report) are run as scripts; the virtual dynamometer
runs the J2522-like schedule on the example disc brake for docs/dyno.md's figure (about 0.2 s
and 0.4 s for its plot).
Everything goes to docs/_generated (not committed).
"""

from __future__ import annotations

import contextlib
import io
import runpy
from pathlib import Path

import stiction as st

ROOT = Path(__file__).resolve().parents[1]


def _model_files() -> list[Path]:
    return sorted((ROOT / "examples").glob("*.toml")) + sorted((ROOT / "examples" / "msl").glob("*.toml"))


def _entry(path: Path, out: Path) -> list[str]:
    model = st.Model.load(path)
    result = model.simulate()
    result.plot(path=out / f"{path.stem}.png").clear()
    where = path.relative_to(ROOT)
    lines = [
        f"## {path.stem}",
        "",
        f"`{where}`: {len(model.components)} components, {len(result.events)} events.",
    ]
    return [*lines, "", f"![{path.stem}]({path.stem}.png)", ""]


def _tutorial(out: Path) -> None:
    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        result = runpy.run_path(str(ROOT / "examples" / "vehicle_launch.py"))["main"]()
    (out / "vehicle_launch.txt").write_text(buffer.getvalue())
    result.plot(
        ["engine.w", "gearbox_in.w"],
        "wheel.w",
        ["clutch.mode", "brake.mode"],
        path=out / "vehicle_launch.png",
    )


def _vehicle_stop(out: Path) -> list[str]:
    """examples/vehicle_stop.py run as a script: its brake-test report and speed, distance."""
    buffer = io.StringIO()
    with contextlib.redirect_stdout(buffer):
        result = runpy.run_path(str(ROOT / "examples" / "vehicle_stop.py"))["main"]()
    result.plot("car.v", "car.s", "disc.T", path=out / "vehicle_stop_report.png").clear()
    report = ["```text", *buffer.getvalue().splitlines(), "```"]
    title = "## vehicle_stop.py: braking a quarter car from 100 km/h"
    return [title, "", *report, "", "![vehicle_stop report](vehicle_stop_report.png)", ""]


def _dyno(out: Path) -> None:
    """examples/dyno: the J2522-like schedule on the disc brake, its report's figure."""
    dyno = ROOT / "examples" / "dyno"
    report = st.dyno(dyno / "disc_brake.toml", dyno / "j2522_like.toml", progress=False)
    report.plot(out / "dyno_j2522_like.png")


def write_gallery(docs: Path) -> None:
    """Run every example into ``docs/_generated``: gallery.md, the plots, the tutorial output."""
    out = docs / "_generated"
    out.mkdir(exist_ok=True)
    lines = ["# Gallery", "", "Every example, run when the documentation is built (`make docs`).", ""]
    for path in _model_files():
        lines += _entry(path, out)
    lines += _vehicle_stop(out)
    (out / "gallery.md").write_text("\n".join(lines))
    _tutorial(out)
    _dyno(out)
