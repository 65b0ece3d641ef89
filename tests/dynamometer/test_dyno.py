"""The virtual dynamometer against closed forms: adiabatic stops (temperature, energy, mean
mu, stop time), cooling with constant convection (its exponential, the time to the IBT), the
exact end of a stop above standstill, and the re-drive hooks it is built on."""

from __future__ import annotations

import math

import pytest

import stiction as st
from stiction.dynamometer import dyno, loads_schedule

J, C, MU, CGEO, FN_PER_BAR, FN_MAX = 2.0, 500.0, 0.4, 0.2, 100.0, 1e5
T0 = 300.0  # K
G = 4.0  # W/K, the cooling models' conductance
T_AMB = 293.15


def brake_model(cooling: bool) -> st.Model:
    """A brake with constant mu heating a capacitor, cooled through G to an ambient or not."""
    m = st.Model("dyno_test")
    m.add("brake", st.Brake(fn_max=FN_MAX, cgeo=CGEO, mu_pos=[[0.0, MU]], peak=1.0, useHeatPort=True))
    m.add("disc", st.HeatCapacitor(C=C, T=T0))
    m.connect("brake.heatPort", "disc.port")
    if cooling:
        m.add("cooling", st.ThermalConductor(G=G))
        m.add("ambient", st.FixedTemperature(T=T_AMB))
        m.connect("disc.port", "cooling.port_a")
        m.connect("cooling.port_b", "ambient.port")
    m.experiment["Tolerance"] = 1e-11
    return m


RIG = f"""
[dyno]
brake = "brake"
flange = "brake.flange_a"
J = {J}
temperature = "disc.T"
fn_per_bar = {FN_PER_BAR}
"""


def section(name: str, w0: float, w1: float, p: float, extra: str = "interval = 0.0") -> str:
    return f'\n[[section]]\nname = "{name}"\nv_initial = {w0}\nv_final = {w1}\npressure = {p}\n{extra}\n'


def test_three_adiabatic_stops_match_the_closed_forms() -> None:
    stops = [(100.0, 0.0, 20.0), (80.0, 20.0, 35.0), (60.0, 10.0, 50.0)]
    text = RIG + "".join(section(f"s{k}", *s, "interval = 5.0") for k, s in enumerate(stops))
    report = dyno(brake_model(cooling=False), loads_schedule(text), progress=False)
    T = T0
    for row, (w0, w1, p) in zip(report.stops.itertuples(), stops):
        energy = J * (w0**2 - w1**2) / 2
        assert row.T_initial + 273.15 == pytest.approx(T, rel=1e-10)
        T += energy / C
        assert row.T_final + 273.15 == pytest.approx(T, rel=1e-10)
        assert row.T_peak == pytest.approx(row.T_final, rel=1e-10)
        assert row.energy == pytest.approx(energy, rel=1e-12)
        assert row.fn == pytest.approx(p * FN_PER_BAR)
        for mu in (row.mu_mean, row.mu_min, row.mu_max):
            assert mu == pytest.approx(MU, rel=1e-8)
        # constant torque: a linear speed fall, ending at the closed-form instant (w1 > 0:
        # the crossing found on the dense output; w1 = 0: the stick event)
        assert row.time == pytest.approx(J * (w0 - w1) / (MU * CGEO * p * FN_PER_BAR), rel=1e-8)
    assert list(report.stops["stop"]) == [1, 1, 1]


def test_cooling_follows_the_exponential_and_stops_at_the_ibt() -> None:
    ibt = 40.0  # °C
    text = (
        RIG
        + section("heat", 100.0, 0.0, 50.0)
        + section("to IBT", 50.0, 0.0, 50.0, f"IBT = {ibt}")
        + section("fixed", 50.0, 0.0, 50.0, "interval = 120.0")
    )
    model = brake_model(cooling=True)
    model.components["disc"] = st.HeatCapacitor(C=C, T=330.0)
    stops = dyno(model, loads_schedule(text), progress=False).stops
    first, second, third = (stops.iloc[k] for k in range(3))
    T1 = first.T_final + 273.15
    # brake released, the disc cools through G alone: T_amb + (T1 - T_amb)·exp(-G·t/C)
    t_ibt = C / G * math.log((T1 - T_AMB) / (ibt + 273.15 - T_AMB))
    assert second.cooling_time == pytest.approx(t_ibt, rel=1e-7)
    assert second.T_initial == pytest.approx(ibt, abs=1e-9)
    T2 = second.T_final + 273.15
    expected = T_AMB + (T2 - T_AMB) * math.exp(-G * 120.0 / C)
    assert third.T_initial + 273.15 == pytest.approx(expected, rel=1e-8)
    assert third.cooling_time == pytest.approx(120.0)


def test_a_drag_holds_the_speed_and_heats_by_the_closed_form() -> None:
    v, p, duration = 30.0, 20.0, 10.0
    drag = f'\n[[section]]\nname = "drag"\nkind = "drags"\nrepeat = 2\nv_initial = {v}\npressure = {p}\nduration = {duration}\ninterval = 1.0\n'
    report = dyno(brake_model(cooling=False), loads_schedule(RIG + drag), progress=False)
    stops, fn = report.stops, p * FN_PER_BAR
    # held through the coupling, which engages sliding at zero slip and locks at its stick
    # event a moment later: the held speed is off by that event's resolution
    assert report.samples["w"].to_numpy() == pytest.approx(v, rel=1e-6)
    energy = MU * CGEO * fn * v * duration  # the motor holds v: the brake's torque times angle
    T = T0
    for row in stops.itertuples():
        assert (row.kind, row.v_final, row.time) == ("drags", v, duration)
        assert row.energy == pytest.approx(energy, rel=1e-6)
        assert row.T_initial + 273.15 == pytest.approx(T, rel=1e-7)
        T += energy / C
        assert row.T_final + 273.15 == pytest.approx(T, rel=1e-7)
        assert row.mu_min == pytest.approx(MU, rel=1e-12) and row.mu_max == pytest.approx(MU, rel=1e-12)
        # a drag's mean takes the work from the integrated dissipation (and the held speed is
        # off as above): closed to about 1e-7
        assert row.mu_mean == pytest.approx(MU, rel=1e-6)


def test_a_drag_longer_than_the_longest_stop_runs_its_whole_duration() -> None:
    """The run's StopTime counts a drag's duration, not the rig's longest stop (120 s)."""
    v, p, duration = 2.0, 1.0, 300.0
    drag = f'\n[[section]]\nname = "long drag"\nkind = "drags"\nv_initial = {v}\npressure = {p}\nduration = {duration}\n'
    (row,) = dyno(brake_model(cooling=False), loads_schedule(RIG + drag), progress=False).stops.itertuples()
    assert row.time == duration
    assert row.energy == pytest.approx(MU * CGEO * p * FN_PER_BAR * v * duration, rel=1e-6)


def test_a_target_deceleration_and_the_wear_column() -> None:
    """With mu_nominal the brake's mu, the controller's first clamp force meets the
    deceleration exactly and it measures that mu in every sample, so the clamp force stays
    J·alpha/(mu·cgeo), stop after stop; the brake's own energy
    wear law (docs/wear.md) wears alpha·E per stop, the column is its wearVolume's growth and
    the thickness left falls by the worn volume over the pad's area."""
    alpha, decel, area, thickness = 2e-12, 25.0, 4e-3, 0.011  # m³/J; rad/s²; m²; m
    model = brake_model(cooling=False)
    model.components["brake"].params["wear"] = st.wear.Energy(alpha=alpha, A=area, thickness=thickness)
    rig = RIG + f"mu_nominal = {MU}\n"
    text = (
        rig
        + f'\n[[section]]\nname = "decel"\nrepeat = 2\nv_initial = 100.0\nv_final = 20.0\ndecel = {decel}\ninterval = 1.0\n'
    )
    stops = dyno(model, loads_schedule(text), progress=False).stops
    worn = 0.0
    for row in stops.itertuples():
        assert row.time == pytest.approx(80.0 / decel, rel=1e-10)
        assert row.fn == pytest.approx(J * decel / (MU * CGEO), rel=1e-8)
        assert row.energy == pytest.approx(J * (100.0**2 - 20.0**2) / 2, rel=1e-12)
        assert row.wear == pytest.approx(alpha * row.energy, rel=1e-8)
        worn += row.wear
        assert row.thickness == pytest.approx(thickness - worn / area, rel=1e-10)


def test_the_report_figure_shows_each_section_and_is_written(tmp_path) -> None:
    pytest.importorskip("matplotlib")
    stops = [(100.0, 0.0, 20.0), (80.0, 20.0, 35.0)]
    text = RIG + "".join(section(n, *s) for n, s in zip(("fade 1", "recovery 1"), stops))
    report = dyno(brake_model(cooling=False), loads_schedule(text), progress=False)
    fig = report.plot()
    mu_axes, *_, fade_axes, _twin = fig.axes
    assert [t.get_text() for t in mu_axes.get_legend().get_texts()] == ["fade 1", "recovery 1"]
    assert [line.get_label() for line in fade_axes.get_lines()] == ["fade 1", "recovery 1"]
    files = report.write(tmp_path)
    assert [f.name for f in files] == ["stops.parquet", "stops.csv", "samples.parquet", "dyno.png"]
    assert (tmp_path / "dyno.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
