"""An FMU carries every platform's runtime that is built (issue 29): with the Windows runtime
cross-compiled (`make fmu-windows`), FMPy (an independent FMI tool) sees both platforms in one
FMU, and the DLL exports every FMI function the Linux library does."""

from __future__ import annotations

import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest
from paths import MSL_EXAMPLES

import stiction as st
from stiction.fmu.export import other_runtimes, runtime_library

WINDOWS = other_runtimes().get("win32")
needs_windows = pytest.mark.skipif(WINDOWS is None, reason="no Windows runtime built (make fmu-windows)")


def exported_symbols(library: Path, objdump: str) -> set[str]:
    """The fmi2*/fmi3* functions a library exports, as objdump lists them."""
    listing = subprocess.run(
        [objdump, "-p" if library.suffix == ".dll" else "-T", str(library)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return set(re.findall(r"\b(fmi[23][A-Z]\w+)\b", listing))


@needs_windows
@pytest.mark.parametrize(
    ("version", "folders"), [(2, {"linux64", "win64"}), (3, {"x86_64-linux", "x86_64-windows"})]
)
def test_one_fmu_carries_the_linux_and_the_windows_runtime(
    tmp_path: Path, version: int, folders: set[str]
) -> None:
    fmpy = pytest.importorskip("fmpy")
    model = st.Model.load(MSL_EXAMPLES / "CoupledClutches.toml")
    fmu = model.to_fmu(tmp_path / "cc.fmu", fmi_version=version)
    with zipfile.ZipFile(fmu) as z:
        binaries = {Path(n).parent.name for n in z.namelist() if n.startswith("binaries/")}
    assert binaries == folders
    assert {"linux64", "win64"} <= set(fmpy.supported_platforms(str(fmu)))
    result = fmpy.simulate_fmu(str(fmu))  # the Linux binary still runs
    assert result["J1.w"][-1] == pytest.approx(model.simulate()["J1.w"][-1], rel=1e-9)


@needs_windows
def test_the_dll_exports_what_the_linux_library_exports() -> None:
    mingw = shutil.which("x86_64-w64-mingw32-objdump")
    if mingw is None or shutil.which("objdump") is None:
        pytest.skip("no objdump for PE files")
    windows = exported_symbols(WINDOWS, mingw)
    linux = exported_symbols(runtime_library(), "objdump")
    assert len(linux) > 60 and windows == linux
