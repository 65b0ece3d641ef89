"""The dyno on the brake physics of issue 32 together: a faded brake's stops against the
adiabatic closed form with linear fade (crates/stiction-core/tests/fade.rs's parametrisation),
cooling through a speed-dependent convection at the spin speed, a pad worn out mid-schedule,
and the example disc brake (fade and recovery in the J2522-like schedule, the same run from
its .mo export)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner
from paths import EXAMPLES, REPO

import stiction as st
from stiction.cli.app import main
from stiction.dynamometer import LEVELS, dyno, loads_schedule

# fade.rs's adiabatic stop: J = 2 kg·m², w0 = 100 rad/s, fn = 500 N, cgeo = 1, C = 1000 J/K,
# T0 = 293.15 K, mu = mu0 − beta·(T − T0) with mu0 = 0.4, beta = 0.01 /K; a stop heats 10 K.
J, W0, FN, C, T0, MU0, BETA = 2.0, 100.0, 500.0, 1000.0, 293.15, 0.4, 0.01
T_END = T0 + 35.0  # the fade table's last row: three stops stay on its one linear segment


def faded_brake() -> st.Model:
    """mu_pos holds mu0, mu_T is linear from 1 at T0 to 1 − beta/mu0·35 at T0 + 35 K."""
    m = st.Model("faded")
    mu_T = [[T0, 1.0], [T_END, 1.0 - BETA / MU0 * (T_END - T0)]]
    m.add("brake", st.Brake(fn_max=1e5, cgeo=1.0, mu_pos=[[0.0, MU0]], peak=1.0, useHeatPort=True, mu_T=mu_T))
    m.add("disc", st.HeatCapacitor(C=C, T=T0))
    m.connect("brake.heatPort", "disc.port")
    m.experiment["Tolerance"] = 1e-11
    return m


RIG = f'[dyno]\nbrake = "brake"\nflange = "brake.flange_a"\nJ = {J}\ntemperature = "disc.T"\nfn_per_bar = 100.0\n'


def test_faded_stops_follow_the_adiabatic_closed_form() -> None:
    """Stop k starts at T_k = T0 + 10 K·(k − 1) with mu_k = mu0 − beta·(T_k − T0); within it
    mu(w) = A + B·w², A = mu_k − beta·J·w0²/(2C), B = beta·J/(2C). The dyno's mean mu (work over
    the 10–80 % window by the sliding angle) is the integral ∫mu dphi / ∫dphi over the window,
    (w_a² − w_b²)·B / ln((A + B·w_a²)/(A + B·w_b²)); every sample is mu0 times the mu_T factor
    at the sample's temperature; the stop time is J/(fn·√(AB))·atan(w0·√(B/A))."""
    text = (
        RIG + '\n[[section]]\nname = "fade"\nrepeat = 3\nv_initial = 100.0\npressure = 5.0\ninterval = 0.0\n'
    )
    report = dyno(faded_brake(), loads_schedule(text), progress=False)
    B = BETA * J / (2 * C)
    for k, row in enumerate(report.stops.itertuples()):
        T_k = T0 + k * J * W0**2 / (2 * C)
        assert row.T_initial + 273.15 == pytest.approx(T_k, rel=1e-10)
        assert row.T_final + 273.15 == pytest.approx(T_k + J * W0**2 / (2 * C), rel=1e-10)
        A = MU0 - BETA * (T_k - T0) - BETA * J * W0**2 / (2 * C)
        wa, wb = (1 - LEVELS[0]) * W0, (1 - LEVELS[-1]) * W0
        mean = (wa**2 - wb**2) * B / math.log((A + B * wa**2) / (A + B * wb**2))
        assert row.mu_mean == pytest.approx(mean, rel=1e-8)
        assert row.mu_max == pytest.approx(A + B * wa**2, rel=1e-8)
        assert row.mu_min == pytest.approx(A + B * wb**2, rel=1e-8)
        assert row.time == pytest.approx(
            J / (FN * math.sqrt(A * B)) * math.atan(W0 * math.sqrt(B / A)), rel=1e-8
        )
    # the faded mean falls stop by stop as the disc heats: about 0.36, 0.26, 0.16
    assert np.all(np.diff(report.stops["mu_mean"]) < -0.09)
    samples = report.samples
    factor = 1.0 - BETA / MU0 * (samples["T"] + 273.15 - T0)
    np.testing.assert_allclose(samples["mu"], MU0 * factor, rtol=1e-9)


def test_cooling_between_stops_uses_the_convection_at_the_spin_speed() -> None:
    """Gc over |w| (SpeedSensor → Abs → CombiTable1Ds → Convection.Gc): released, the inertia
    spins at the next stop's initial speed, so the disc cools as T_a + (T1 − T_a)·exp(−Gc(w0)·t/C),
    for a fixed interval and to an IBT alike."""
    table, T_a, C_disc = [[0.0, 2.0], [100.0, 12.0]], 300.0, 500.0
    m = st.Model("convected")
    m.add("brake", st.Brake(fn_max=1e5, cgeo=1.0, mu_pos=[[0.0, MU0]], peak=1.0, useHeatPort=True))
    m.add("disc", st.HeatCapacitor(C=C_disc, T=T_a))
    m.add("speed", st.SpeedSensor())
    m.add("absSpeed", st.Abs())
    m.add("gcTable", st.CombiTable1Ds(table=table))
    m.add("convection", st.Convection())
    m.add("ambient", st.FixedTemperature(T=T_a))
    for a, b in [
        ("brake.heatPort", "disc.port"),
        ("brake.flange_b", "speed.flange"),
        ("speed.w", "absSpeed.u"),
        ("absSpeed.y", "gcTable.u"),
        ("gcTable.y[1]", "convection.Gc"),
        ("disc.port", "convection.solid"),
        ("convection.fluid", "ambient.port"),
    ]:
        m.connect(a, b)
    m.experiment["Tolerance"] = 1e-11
    ibt = 33.0  # °C, the disc is at about 38 °C after the second stop
    text = RIG + "".join(
        f'\n[[section]]\nname = "s{k}"\nv_initial = {w}\npressure = 20.0\n{extra}\n'
        for k, (w, extra) in enumerate(
            [(100.0, "interval = 0.0"), (60.0, "interval = 100.0"), (30.0, f"IBT = {ibt}")]
        )
    )
    first, second, third = dyno(m, loads_schedule(text), progress=False).stops.itertuples()
    gc = lambda w: float(np.interp(w, [r[0] for r in table], [r[1] for r in table]))
    T1 = first.T_final + 273.15
    expected = T_a + (T1 - T_a) * math.exp(-gc(60.0) * 100.0 / C_disc)  # Gc(60) = 8 W/K
    assert second.T_initial + 273.15 == pytest.approx(expected, rel=1e-8)
    T2 = second.T_final + 273.15
    t_ibt = C_disc / gc(30.0) * math.log((T2 - T_a) / (ibt + 273.15 - T_a))  # Gc(30) = 5 W/K
    assert third.cooling_time == pytest.approx(t_ibt, rel=1e-7)
    assert third.T_initial == pytest.approx(ibt, abs=1e-9)


def worn_brake() -> st.Model:
    """Each 100 rad/s stop (10 kJ) wears alpha·10 kJ = 1e-5 m³, 10 mm of a 10 cm² pad: the
    pad (50 mm, limit 20 mm) wears out halfway through the third stop of 100 rad/s."""
    m = st.Model("worn")
    wear = st.wear.Energy(alpha=1e-9, A=1e-3, thickness=0.05, thickness_min=0.02)
    m.add("brake", st.Brake(fn_max=1e5, cgeo=1.0, mu_pos=[[0.0, MU0]], peak=1.0, useHeatPort=True, wear=wear))
    m.add("disc", st.HeatCapacitor(C=C, T=T0))
    m.connect("brake.heatPort", "disc.port")
    m.experiment["Tolerance"] = 1e-10
    return m


WORN = (
    RIG
    + '\n[[section]]\nname = "bed"\nrepeat = 2\nv_initial = 50.0\npressure = 5.0\ninterval = 0.0\n'
    + '\n[[section]]\nname = "wear"\nrepeat = 4\nv_initial = 100.0\npressure = 5.0\ninterval = 0.0\n'
)


def test_a_pad_worn_out_mid_schedule_ends_the_run_cleanly(tmp_path) -> None:
    """Two 2.5 kJ stops wear 5 mm; the 'wear' section's stops 10 mm each: the pad reaches its
    20 mm limit in that section's third stop (the schedule's fifth), whose row is not kept."""
    report = dyno(worn_brake(), loads_schedule(WORN), progress=False)
    assert not report.completed
    assert len(report) == 4
    assert list(report.stops["section"]) == ["bed", "bed", "wear", "wear"]
    assert report.stops["thickness"].iloc[-1] == pytest.approx(0.05 - 0.005 - 0.020, rel=1e-9)
    worn = report.worn_out
    assert (worn["index"], worn["section"], worn["stop"]) == (5, "wear", 3)
    assert "'brake'" in worn["message"] and "thickness_min" in worn["message"]
    assert "stop 5 (section 'wear', stop 3)" in report.summary()
    # the command line writes the stops done and says where the pad wore out
    model = tmp_path / "worn.toml"
    worn_brake().save(model)
    schedule = tmp_path / "worn_schedule.toml"
    schedule.write_text(WORN, encoding="utf-8")
    out = tmp_path / "report"
    result = CliRunner().invoke(
        main, ["dyno", str(model), str(schedule), "-o", str(out), "--quiet", "--no-plots"]
    )
    assert result.exit_code == 0, result.output
    assert "stopped early: 4 stops; the pad wore out in stop 5 (section 'wear', stop 3)" in result.output
    assert len(pd.read_csv(out / "stops.csv")) == 4
    assert (out / "worn_out.txt").read_text(encoding="utf-8") == report.summary() + "\n"


def test_a_pad_worn_out_in_the_first_controlled_stop_leaves_the_table_empty() -> None:
    """A 200 rad/s stop (40 kJ) wears 40 mm of the 30 mm the pad has to its limit: the
    schedule's first stop, under deceleration control, wears it out; no row, the control
    columns still there."""
    text = RIG + f"mu_nominal = {MU0}\n"
    text += '\n[[section]]\nname = "decel"\nrepeat = 2\nv_initial = 200.0\ndecel = 20.0\ninterval = 0.0\n'
    report = dyno(worn_brake(), loads_schedule(text), progress=False)
    assert not report.completed and len(report) == 0
    assert (report.worn_out["index"], report.worn_out["section"], report.worn_out["stop"]) == (1, "decel", 1)
    assert {"decel", "missed"} <= set(report.stops.columns)


@pytest.fixture(scope="module")
def example_report() -> st.DynoReport:
    """The J2522-like schedule on the example disc brake (about 0.3 s)."""
    return dyno(EXAMPLES / "dyno" / "disc_brake.toml", EXAMPLES / "dyno" / "j2522_like.toml", progress=False)


def test_the_example_disc_brake_fades_and_recovers_and_wears(example_report: st.DynoReport) -> None:
    """examples/dyno/disc_brake.toml on the J2522-like schedule: each fade section heats the
    disc past 400 °C and its mean mu falls to below 60 % of the characteristic value (mu_T
    halves above 350–400 °C); the recovery at IBT 100 °C is back within 1 % at once (the model
    has no friction-film memory); the pad wears by the Arrhenius law, faster in the fade."""
    report = dyno(
        EXAMPLES / "dyno" / "disc_brake.toml", EXAMPLES / "dyno" / "j2522_like.toml", progress=False
    )
    assert report.completed and len(report) == 205
    characteristic = report.section("characteristic 3")["mu_mean"].mean()
    assert 0.38 < characteristic < 0.41
    for n in (1, 2):
        fade, recovery = report.section(f"fade {n}"), report.section(f"recovery {n}")
        assert fade["T_peak"].max() > 400.0
        assert fade["mu_mean"].iloc[-1] < 0.6 * characteristic
        assert fade["mu_mean"].iloc[0] == pytest.approx(characteristic, rel=0.01)
        assert recovery["mu_mean"].to_numpy() == pytest.approx(characteristic, rel=0.01)
        # per MJ, the hot end of the fade wears several times what a characteristic stop does
        per_joule = lambda rows: (rows["wear"] / rows["energy"]).to_numpy()
        assert per_joule(fade)[-1] > 3 * per_joule(report.section("characteristic 3")).max()
    assert np.all(np.diff(report.stops["thickness"]) < 0)
    assert 0.008 < report.stops["thickness"].iloc[-1] < 0.0105


def test_the_example_disc_brake_runs_the_same_from_its_modelica_export(tmp_path) -> None:
    """The dyno accepts .mo models: the example exported with to_modelica (fade as modifiers of
    Stiction.Components.Brake, wear as its annotation, the cooling as MSL classes) runs a
    schedule bit for bit as the TOML model does."""
    model = st.Model.load(EXAMPLES / "dyno" / "disc_brake.toml")
    model.to_modelica(tmp_path / "disc_brake.mo")
    schedule = EXAMPLES / "dyno" / "j2522_like.toml"
    text = schedule.read_text(encoding="utf-8")
    short = loads_schedule(text[: text.index('name = "burnish"')].rsplit("[[section]]", 1)[0])
    toml_run = dyno(model, short, progress=False).stops
    mo_run = dyno(tmp_path / "disc_brake.mo", short, progress=False).stops
    assert len(toml_run) == 30
    pd.testing.assert_frame_equal(toml_run, mo_run, check_exact=True)


def test_the_table_in_the_docs_is_the_examples_run(example_report: st.DynoReport) -> None:
    """docs/dyno.md's excerpt of the fade and recovery: every row as the run gives it, to the
    digits the page shows."""
    lines = (REPO / "docs" / "dyno.md").read_text(encoding="utf-8").splitlines()
    start = lines.index(
        next(line for line in lines if line.startswith("| index | section | stop | pressure"))
    )
    rows = [line.strip("|").split("|") for line in lines[start + 2 :] if line.startswith("|")]
    rows = rows[: next((k for k, r in enumerate(rows) if not r[0].strip().isdigit()), len(rows))]
    assert len(rows) == 10
    stops = example_report.stops.set_index("index")
    for cells in rows:
        index, section, stop, *numbers = (c.strip() for c in cells)
        row = stops.loc[int(index)]
        assert (row["section"], row["stop"]) == (section, int(stop))
        run = [row["pressure"], row["pressure_max"], row["T_initial"], row["T_peak"], row["mu_mean"]]
        run += [row["mu_min"], row["mu_max"], row["time"], row["decel_mean"], row["wear"] * 1e9]
        assert len(numbers) == len(run)
        for shown, value in zip(numbers, run):
            decimals = len(shown.split(".")[1]) if "." in shown else 0
            assert float(shown) == pytest.approx(round(value, decimals), abs=1e-12), (index, shown, value)
