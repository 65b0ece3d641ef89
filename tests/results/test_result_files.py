"""Result files: .mat (Dymola/OpenModelica MATLAB v4) read back by scipy and DyMat equals
the CSV to full precision, data_1 holds the parameters, event instants appear twice;
Parquet and CSV read back exactly; -o picks the format by extension and refuses others;
--outputs keeps names and globs; compare reads all three formats."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest
from paths import MSL_DATA, REPO

import stiction as st

EXAMPLE = REPO / "examples" / "msl" / "CoupledClutches.toml"
MSL_DIR = MSL_DATA


@cache
def _result() -> st.Result:
    return st.Model.load(EXAMPLE).simulate()


def _mat_names(m: dict, key: str) -> list[str]:
    chars = m[key]  # binTrans: one column of characters per variable
    return ["".join(col).rstrip() for col in chars.T]


def test_mat_read_by_scipy_equals_the_csv_to_full_precision(tmp_path: Path) -> None:
    scipy_io = pytest.importorskip("scipy.io")
    r = _result()
    r.to_mat(tmp_path / "r.mat")
    r.to_csv(tmp_path / "r.csv")
    csv = st.Result.load(tmp_path / "r.csv")
    m = scipy_io.loadmat(tmp_path / "r.mat", chars_as_strings=False)
    assert ["".join(row).rstrip() for row in m["Aclass"]] == ["Atrajectory", "1.1", "", "binTrans"]
    names = _mat_names(m, "name")
    info, data1, data2 = m["dataInfo"], m["data_1"], m["data_2"]
    assert names[: len(r.names)] == r.names
    for i, name in enumerate(r.names):
        assert info[0, i] in (0, 2) and info[1, i] == i + 1
        assert np.array_equal(data2[info[1, i] - 1], csv[name]), name
    params = r.parameters
    assert params["clutch1.fn_max"] == 20.0 and params["sin2.phase"] == 1.570796326794897
    for k, name in enumerate(names[len(r.names) :]):
        assert info[0, len(r.names) + k] == 1
        assert data1[info[1, len(r.names) + k] - 1].tolist() == [params[name]] * 2
    assert data1[0].tolist() == [0.0, 1.5]  # time: start and stop


def test_mat_event_instants_appear_twice() -> None:
    r = _result()
    t = r.time
    repeated = t[1:][np.diff(t) == 0]
    assert 0.4 in repeated and 0.9 in repeated  # step1 and step2 switch: left and right rows
    assert any(e.time == pytest.approx(0.4) for e in r.events)


def test_mat_read_by_dymat(tmp_path: Path) -> None:
    dymat = pytest.importorskip("DyMat")
    r = _result()
    r.to_mat(tmp_path / "r.mat")
    d = dymat.DyMatFile(str(tmp_path / "r.mat"))
    for name in ("J1.w", "clutch1.mode", "clutch3.tau", "system.dissipatedEnergy"):
        assert np.array_equal(d.data(name), r[name]), name
    assert np.array_equal(d.abscissa("J1.w", valuesOnly=True), r.time)
    assert d.data("clutch2.peak").tolist() == [1.1, 1.1]


def test_every_format_reads_back_identically(tmp_path: Path) -> None:
    pytest.importorskip("pyarrow")
    r = _result()
    for ext in (".csv", ".mat", ".parquet"):
        path = tmp_path / f"r{ext}"
        r.save(path)
        back = st.Result.load(path)
        assert back.names == r.names, ext
        assert np.array_equal(back.data, r.data), ext
    assert st.Result.load(tmp_path / "r.mat").parameters == r.parameters


def test_outputs_by_name_and_glob(tmp_path: Path) -> None:
    r = _result()
    wanted = {"time", "J1.w", "J2.w", "J3.w", "J4.w", "clutch1.mode"}
    assert r.select(["J*.w", "clutch1.mode"]) == [n for n in r.names if n in wanted]  # column order
    with pytest.raises(KeyError, match="did you mean"):
        r.select(["J1.ww"])
    with pytest.raises(KeyError, match="matches"):
        r.select(["Q*"])
    r.to_csv(tmp_path / "few.csv", outputs=["J?.w"])
    assert st.Result.load(tmp_path / "few.csv").names == ["time", "J1.w", "J2.w", "J3.w", "J4.w"]


def test_cli_format_by_extension(tmp_path: Path, cli_runner) -> None:
    from stiction.cli import main

    bad = cli_runner.invoke(main, ["simulate", str(EXAMPLE), "-o", str(tmp_path / "r.xlsx")])
    assert bad.exit_code == 2 and "unknown result format ('.xlsx')" in bad.stderr
    assert not (tmp_path / "r.xlsx").exists()
    out = tmp_path / "r.mat"
    done = cli_runner.invoke(
        main, ["simulate", str(EXAMPLE), "-o", str(out), "--outputs", "J*.w,clutch*.mode"]
    )
    assert done.exit_code == 0, done.stderr
    back = st.Result.load(out)
    wanted = {"time", "J1.w", "J2.w", "J3.w", "J4.w", "clutch1.mode", "clutch2.mode", "clutch3.mode"}
    assert back.names == [n for n in _result().names if n in wanted]
    assert np.array_equal(back["J2.w"], _result()["J2.w"])


@pytest.mark.parametrize("ext", [".mat", ".parquet", ".csv"])
def test_compare_reads_every_format(ext: str, tmp_path: Path, cli_runner) -> None:
    if ext == ".parquet":
        pytest.importorskip("pyarrow")
    from stiction.cli import main

    out = tmp_path / f"r{ext}"
    _result().save(out)
    done = cli_runner.invoke(main, ["compare", str(out), str(MSL_DIR / "CoupledClutches.csv")])
    assert done.exit_code == 0, done.stdout + done.stderr
    assert "11/11 signals passed" in done.stdout
    # and the other way round: our .mat as the reference
    done = cli_runner.invoke(main, ["compare", str(MSL_DIR / "CoupledClutches.csv"), str(out)])
    assert "passed" in done.stdout


def test_csv_written_by_the_core_keeps_every_digit(tmp_path: Path) -> None:
    names = ["time", "x", "c.mode"]
    data = np.array([[0.0, 1 / 3, -1.0], [1e-300, -2.5e17, 2.0], [0.1, np.pi, 0.0]])
    st.Result(names, data).to_csv(tmp_path / "x.csv")
    text = (tmp_path / "x.csv").read_text()
    assert text.splitlines()[0] == '"time","x","c.mode"'
    assert text.splitlines()[1].endswith(",-1")
    assert np.array_equal(st.Result.load(tmp_path / "x.csv").data, data)


def test_load_reads_a_bin_normal_result_written_by_another_writer(tmp_path: Path) -> None:
    """A Dymola-style "binNormal" file (one row per variable name, data_2 with one column per
    variable, a negative dataInfo index for a variable stored with the opposite sign, a
    constant in data_1), written by scipy, loads with the right columns and parameters."""
    scipy_io = pytest.importorskip("scipy.io")
    names = ["time", "J.w", "J.flange_a.tau", "J.J"]
    width = max(map(len, names))
    t = np.array([0.0, 0.5, 0.5, 1.0])  # an event at 0.5: the instant twice
    w = np.array([1.0, 1.5, 1.5, 2.0])
    tau = np.array([0.25, -0.5, 0.75, 1.0])
    scipy_io.savemat(
        tmp_path / "dymola.mat",
        {
            "Aclass": np.array(["Atrajectory", "1.1        ", "           ", "binNormal  "]),
            "name": np.array([n.ljust(width) for n in names]),
            "description": np.array(["Time".ljust(8), "", "", ""], dtype=f"<U{8}"),
            "dataInfo": np.array(
                [[0, 1, 0, -1], [2, 2, 0, -1], [2, -3, 0, -1], [1, 2, 0, 0]], dtype=np.int32
            ),
            "data_1": np.array([[0.0, 2.0], [1.0, 2.0]]),
            "data_2": np.column_stack([t, w, -tau]),
        },
        format="4",
    )
    r = st.Result.load(tmp_path / "dymola.mat")
    assert r.names == ["time", "J.w", "J.flange_a.tau"]
    assert (
        np.array_equal(r.time, t) and np.array_equal(r["J.w"], w) and np.array_equal(r["J.flange_a.tau"], tau)
    )
    assert r.parameters == {"J.J": 2.0}


def test_load_refuses_what_is_not_a_result(tmp_path: Path) -> None:
    path = tmp_path / "x.mat"
    path.write_bytes(b"\x00" * 7)
    with pytest.raises(ValueError, match="not a Dymola/OpenModelica result"):
        st.Result.load(path)
    with pytest.raises(ValueError, match="unknown result format"):
        st.Result.load(tmp_path / "x.h5")
