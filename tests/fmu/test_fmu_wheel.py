"""The FMU runtime ships inside the wheel: built with maturin, installed into a fresh virtual
environment (its dependencies borrowed from this one, so no network), it exports an FMU that
FMPy runs — no Rust toolchain and no build tree involved on that side; and `stiction bench`
finds its default models in the installed package, not in a checkout."""

from __future__ import annotations

import shutil
import site
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest
from paths import REPO

ROOT = REPO
MATURIN = Path(sys.executable).parent / "maturin"

SCRIPT = """
import numpy as np, fmpy, stiction as st
from stiction.fmu import runtime_library
assert str(runtime_library()).startswith({env!r}), runtime_library()
m = st.Model.load({model!r})
out = fmpy.simulate_fmu(str(m.to_fmu("cc.fmu", outputs=["J1.w"])), stop_time=1.5, output_interval=0.01)
ref = m.simulate()
from click.testing import CliRunner
from stiction.cli import main
from stiction.cli.bench import BENCH_MODELS
assert str(BENCH_MODELS).startswith({env!r}), BENCH_MODELS  # bench's models ship in the wheel
bench = CliRunner().invoke(main, ["bench", "--repeat", "1", "--warmup", "0"])
assert bench.exit_code == 0 and "HeatLosses" in bench.output, bench.output
print(np.max(np.abs(out["J1.w"] - np.interp(out["time"], ref.time, ref["J1.w"]))))
"""


@pytest.mark.slow
@pytest.mark.skipif(not MATURIN.exists() or shutil.which("cargo") is None, reason="needs maturin and cargo")
def test_the_wheel_exports_fmus_in_a_fresh_environment(tmp_path: Path) -> None:
    build = [str(MATURIN), "build", "--release", "--quiet", "-o", str(tmp_path / "dist")]
    subprocess.run(build, cwd=ROOT, check=True, capture_output=True)
    wheel = next((tmp_path / "dist").glob("*.whl"))
    env = tmp_path / "env"
    venv.create(env, with_pip=False)
    python = env / "bin" / "python"
    packages = next(env.glob("lib/python*/site-packages"))
    with zipfile.ZipFile(wheel) as z:  # what pip does with a wheel, less the scripts
        z.extractall(packages)
    borrowed = packages / "borrowed.pth"
    borrowed.write_text("\n".join(site.getsitepackages()) + "\n")
    script = SCRIPT.format(model=str(ROOT / "examples" / "msl" / "CoupledClutches.toml"), env=str(env))
    run = subprocess.run([python, "-c", script], cwd=tmp_path, check=False, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert float(run.stdout.split()[-1]) < 1e-9
