"""The dyno's deceleration controller (python/stiction/dynamometer/control.py): a faded brake
held at its target deceleration to the sampled controller's bound, the mean and peak pressure
against the closed form, an unreachable target saturated at p_max and flagged, and the tables
of pressure-only schedules unchanged by the controller's existence."""

from __future__ import annotations

import math

import pytest
from paths import EXAMPLES

import stiction as st
from stiction.dynamometer import Schedule, ScheduleError, dyno, loads_schedule

# fade.rs's adiabatic brake (as test_dyno_physics.py): mu = mu0 − beta·(T − T0) over the disc
# temperature, and adiabatic T = T0 + J·(w0² − w²)/(2·C): mu(w) = A + B·w² whatever the
# pressure did, A = mu0 − B·w0², B = beta·J/(2·C).
J, W0, W1, C, T0, MU0, BETA, FN_PER_BAR = 2.0, 100.0, 10.0, 1000.0, 293.15, 0.4, 0.01, 100.0
DECEL = 20.0  # rad/s²: 4.5 s from 100 to 10 rad/s, the disc heats 9.9 K, mu falls 0.4 → 0.301
B = BETA * J / (2 * C)
A = MU0 - B * W0**2


def faded_brake() -> st.Model:
    m = st.Model("faded")
    mu_T = [[T0, 1.0], [T0 + 35.0, 1.0 - BETA / MU0 * 35.0]]
    m.add("brake", st.Brake(fn_max=1e5, cgeo=1.0, mu_pos=[[0.0, MU0]], peak=1.0, useHeatPort=True, mu_T=mu_T))
    m.add("disc", st.HeatCapacitor(C=C, T=T0))
    m.connect("brake.heatPort", "disc.port")
    m.experiment["Tolerance"] = 1e-11
    return m


def schedule(extra_rig: str = "", sections: str = "") -> Schedule:
    rig = f'[dyno]\nbrake = "brake"\nflange = "brake.flange_a"\nJ = {J}\ntemperature = "disc.T"\n'
    rig += f"fn_per_bar = {FN_PER_BAR}\nmu_nominal = {MU0}\n" + extra_rig
    stop = (
        f'\n[[section]]\nname = "fade"\nv_initial = {W0}\nv_final = {W1}\ndecel = {DECEL}\ninterval = 0.0\n'
    )
    return loads_schedule(rig + (sections or stop))


def mu(w: float) -> float:
    return A + B * w * w


@pytest.mark.parametrize("rate", [100.0, 1000.0])
def test_a_fading_brake_is_held_at_its_target_deceleration(rate: float) -> None:
    """A sample's deceleration is alpha·mu_k/mu_(k−1): off by at most |dmu/dt|·dt/mu. Here
    dmu/dt = −beta·J·alpha·w/C, largest at w0, and mu smallest at w1: the bound
    beta·J·alpha·w0/(C·mu(w1)·f) (1.3e-3 at 100 Hz). The mean deceleration over 10–80 %, the
    stop time (w0 − w1)/alpha and the mean mu (mu(w) weighted by w dw at constant alpha:
    A + B·(w10² + w80²)/2) hold to it; the mean pressure is the closed form's time mean of
    J·alpha/(mu(w(t))·cgeo), J/(T·√(AB))·[atan(w·√(B/A))] from w1 to w0, over fn_per_bar,
    the peak J·alpha/mu(w1)/fn_per_bar."""
    bound = BETA * J * DECEL * W0 / (C * mu(W1) * rate)
    row = dyno(faded_brake(), schedule(f"control_rate = {rate}\n"), progress=False).stops.iloc[0]
    assert row.decel == DECEL and not row.missed
    assert 0.1 * bound < 1 - row.decel_mean / DECEL < bound  # a fading pad lags the controller
    assert row.time == pytest.approx((W0 - W1) / DECEL, rel=bound)
    w10, w80 = W0 - 0.1 * (W0 - W1), W0 - 0.8 * (W0 - W1)
    assert row.mu_mean == pytest.approx(A + B * (w10**2 + w80**2) / 2, rel=bound)
    T = (W0 - W1) / DECEL
    atan = lambda w: math.atan(w * math.sqrt(B / A))
    fn_mean = J / (T * math.sqrt(A * B)) * (atan(W0) - atan(W1))
    assert row.pressure == pytest.approx(fn_mean / FN_PER_BAR, rel=2 * bound)
    assert row.fn == pytest.approx(fn_mean, rel=2 * bound)
    assert row.pressure_max == pytest.approx(J * DECEL / mu(W1) / FN_PER_BAR, rel=2 * bound)
    # the feed-forward alone would have run the stop at J·alpha/mu0: 15 % too slow at the end
    assert row.pressure_max > 1.3 * J * DECEL / MU0 / FN_PER_BAR


def test_an_unreachable_target_saturates_at_p_max_and_is_flagged() -> None:
    """With p_max below what the target needs, the controller holds p_max from the first
    sample (the feed-forward clipped): the stop is a constant-pressure stop of the faded brake,
    its mean pressure p_max, its time the adiabatic closed form
    J/(cgeo·fn·√(AB))·[atan(w·√(B/A))] from w1 to w0, flagged missed; the next stop, with a
    reachable target, is not. A pressure stop in the same schedule reports its pressure as
    the peak and is not flagged; the report's summary names the stop."""
    p_max = 0.5 * J * DECEL / MU0 / FN_PER_BAR  # half what the cold pad needs
    sections = (
        f'\n[[section]]\nname = "hard"\nv_initial = {W0}\nv_final = {W1}\ndecel = {DECEL}\ninterval = 0.0\n'
        f'\n[[section]]\nname = "press"\nv_initial = {W0}\nv_final = {W1}\npressure = 1.0\ninterval = 0.0\n'
        f'\n[[section]]\nname = "soft"\nv_initial = {W0}\nv_final = {W1}\ndecel = 1.0\ninterval = 0.0\n'
    )
    report = dyno(faded_brake(), schedule(f"p_max = {p_max}\n", sections), progress=False)
    stops = report.stops
    assert report.summary() == "3 stops; 1 missed their target deceleration (at p_max): index 1"
    hard, press, soft = (stops.iloc[k] for k in range(3))
    assert hard.missed and not press.missed and not soft.missed
    assert hard.pressure_max == pytest.approx(p_max, rel=1e-14)
    assert hard.pressure == pytest.approx(p_max, rel=1e-12)
    fn = p_max * FN_PER_BAR
    atan = lambda w: math.atan(w * math.sqrt(B / A))
    assert hard.time == pytest.approx(J / (fn * math.sqrt(A * B)) * (atan(W0) - atan(W1)), rel=1e-8)
    assert hard.decel_mean < 0.6 * DECEL
    assert (press.pressure, press.pressure_max, math.isnan(press.decel)) == (1.0, 1.0, True)
    assert soft.decel_mean == pytest.approx(1.0, rel=1e-3)


def test_a_pressure_only_schedule_gives_the_table_it_gave_before_the_controller() -> None:
    """Pinned from the run before the controller existed (commit 3c3008d): the example disc
    brake through two pressure sections of the J2522-like schedule gives the same columns and,
    bit for bit, the same values."""
    text = (EXAMPLES / "dyno" / "j2522_like.toml").read_text(encoding="utf-8")

    def section(name: str) -> str:
        at = text.index(f'name = "{name}"')
        start, end = text.rindex("[[section]]", 0, at), text.find("[[section]]", at)
        return text[start:end]

    short = loads_schedule(
        text[: text.index("[[section]]")] + section("speed/pressure 80 km/h") + section("cold")
    )
    stops = dyno(EXAMPLES / "dyno" / "disc_brake.toml", short, progress=False).stops
    assert list(stops.columns) == [
        *("index", "section", "kind", "stop", "v_initial", "v_final", "pressure", "fn", "T_initial"),
        *("T_peak", "T_final", "mu_mean", "mu_min", "mu_max", "time", "energy", "cooling_time"),
        *("t_start", "wear", "thickness"),
    ]
    pinned = {
        "mu_mean": (0.36978658930550207, 0.3911671570859595, 0.38351471979307905),
        "time": (7.559464593629968, 0.8947568325467046, 2.1197642613817607),
        "T_peak": (55.78138196413494, 135.94248925239066, 51.77551000152772),
        "wear": (4.999999999801544e-08, 5.00000000017397e-08, 1.640624984817255e-08),
    }
    for column, values in pinned.items():
        assert tuple(stops[column].iloc[[0, 7, 10]]) == values, column


def test_controller_settings_are_checked() -> None:
    with pytest.raises(ScheduleError, match=r"control_rate = 0 must be positive"):
        schedule("control_rate = 0\n")
    rig = f'[dyno]\nbrake = "b"\ninertia = "J"\np_max = 80.0\n[[section]]\nv_initial = 1.0\ndecel = {DECEL}\n'
    with pytest.raises(ScheduleError, match=r"line 4\): p_max \[bar\] needs fn_per_bar"):
        loads_schedule(rig)
