"""ElastoBacklash2 (hard contact) against its closed form: the Backlash example's third branch.

An inertia J at 90° against a fixed flange through an ElastoBacklash2 (c, d, 45° play) is a
piecewise-linear system: free flight in the gap (constant speed), a damped oscillator
``J·s'' + d·s' + c·s = 0`` in contact (s = phi_rel ∓ b/2) while the contact pushes
(``±(c·s + d·s') > 0``), and free flight again once it would pull. MAP-LIB's Backlash.csv has
no column of this branch, so the exact piecewise solution is the reference.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable

import numpy as np
import pytest
from paths import MSL_EXAMPLES

import stiction as st

C, D, J = 2e4, 50.0, 5.0
B_MAX = 0.78539816339745 / 2
PHI0 = 1.570796326794897


def _contact(s0: float, v0: float, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """s(t), s'(t) of J·s'' + d·s' + c·s = 0 from (s0, v0) (underdamped here)."""
    sigma = D / (2 * J)
    wd = math.sqrt(C / J - sigma**2)
    a, b = s0, (v0 + sigma * s0) / wd
    e = np.exp(-sigma * t)
    s = e * (a * np.cos(wd * t) + b * np.sin(wd * t))
    v = e * ((b * wd - sigma * a) * np.cos(wd * t) - (a * wd + sigma * b) * np.sin(wd * t))
    return s, v


def _first_zero(f, t_end: float) -> float:
    """The first sign change of f on (0, t_end], by a fine scan and bisection."""
    grid = np.linspace(0.0, t_end, 20001)[1:]
    values = f(grid)
    k = int(np.argmax(values <= 0.0))
    assert values[k] <= 0.0, "no zero found"
    lo, hi = (grid[k - 1] if k else 0.0), grid[k]
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if f(np.array([mid]))[0] <= 0.0 else (mid, hi)
    return hi


def exact(stop: float) -> tuple[list[tuple[float, str, float, float]], Callable]:
    """The phases [(t_start, kind, phi, w)] of the branch up to `stop` and a sampler."""
    phases = []
    t, phi, w = 0.0, PHI0, 0.0
    pushing = True  # the spring starts compressed, at rest
    while t < stop:
        side = math.copysign(1.0, phi)
        if pushing:
            phases.append((t, "contact", phi, w))
            s0 = phi - side * B_MAX

            def push(tt, s0=s0, w0=w, side=side):
                s, v = _contact(s0, w0, tt)
                return side * (C * s + D * v)

            dt = _first_zero(push, 1.0)
            s, v = _contact(s0, w, np.array([dt]))
            t, phi, w = t + dt, float(s[0]) + side * B_MAX, float(v[0])
            pushing = False  # released: free flight across the gap
        else:
            phases.append((t, "free", phi, w))
            # free flight to the far edge of the gap in the direction of motion
            target = math.copysign(B_MAX, w)
            t, phi = t + (target - phi) / w, target
            pushing = True  # arriving at a contact, the damper pushes at once

    def sample(times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        starts = np.array([p[0] for p in phases])
        phi_out, w_out = np.empty_like(times), np.empty_like(times)
        for i, tt in enumerate(times):
            t0, kind, p0, w0 = phases[int(np.searchsorted(starts, tt, side="right")) - 1]
            if kind == "free":
                phi_out[i], w_out[i] = p0 + w0 * (tt - t0), w0
            else:
                side = math.copysign(1.0, p0)
                s, v = _contact(p0 - side * B_MAX, w0, np.array([tt - t0]))
                phi_out[i], w_out[i] = s[0] + side * B_MAX, v[0]
        return phi_out, w_out

    return phases, sample


@pytest.fixture(scope="module")
def backlash() -> st.Result:
    return st.Model.load(MSL_EXAMPLES / "Backlash.toml").simulate()


def test_elasto_backlash2_follows_its_piecewise_closed_form(backlash: st.Result) -> None:
    phases, sample = exact(1.0)
    assert sum(kind == "contact" for _, kind, _, _ in phases) >= 4  # several impacts
    t = backlash.time
    phi, w = sample(t)
    err_phi = np.abs(backlash["elastoBacklash2.phi_rel"] - phi).max()
    err_w = np.abs(backlash["elastoBacklash2.w_rel"] - w).max()
    # the 2e-3 tube's height is 2e-3 of each signal's range
    assert err_phi < 1e-4 * np.ptp(phi), err_phi
    assert err_w < 1e-4 * np.ptp(w), err_w


def test_elasto_backlash2_events_and_torque_jump(backlash: st.Result) -> None:
    """Each contact start and release is an event row; at a contact start the torque jumps
    from 0 to d·w_rel (ElastoBacklash2's hard contact), and in the gap it is exactly 0."""
    phases, _ = exact(1.0)
    t, tau, w = backlash.time, backlash["elastoBacklash2.tau"], backlash["elastoBacklash2.w_rel"]
    for t0, kind, _, w0 in phases[1:]:
        rows = np.flatnonzero(np.abs(t - t0) < 1e-6)
        assert len(rows) >= 2, (t0, kind)  # the event is recorded twice
        if kind == "contact":
            before, after = tau[rows[0]], tau[rows[-1]]
            assert before == 0.0
            assert after == pytest.approx(D * w[rows[-1]], rel=1e-3)
            assert abs(after) == pytest.approx(D * abs(w0), rel=1e-3)
    gap = np.abs(backlash["elastoBacklash2.phi_rel"]) < B_MAX - 1e-6
    assert gap.any() and np.all(tau[gap] == 0.0)
    # never pulling: the torque has the contact's sign (to rounding at the located release)
    pull = -tau * np.sign(backlash["elastoBacklash2.phi_rel"])
    assert pull.max() < 1e-9 * np.abs(tau).max()


def test_elasto_backlash2_energy_balance(backlash: st.Result) -> None:
    """The initial spring energy = the final kinetic and spring energy + ∫lossPower (the
    damper) + the spring energy left in each contact that stopped pushing (the torque drops to
    0 there, MSL's lossPower leaves it out)."""
    phases, _ = exact(1.0)
    t = backlash.time
    w, phi = backlash["elastoBacklash2.w_rel"], backlash["elastoBacklash2.phi_rel"]
    stretch = np.maximum(np.abs(phi) - B_MAX, 0.0)
    tau = backlash["elastoBacklash2.tau"]
    spring = np.where(tau != 0.0, 0.5 * C * stretch**2, 0.0)
    e0 = 0.5 * C * (PHI0 - B_MAX) ** 2
    e_end = 0.5 * J * w[-1] ** 2 + spring[-1]
    damper = np.trapezoid(backlash["elastoBacklash2.lossPower"], t)
    released = _released(phases)
    assert damper > 0.1 * e0
    assert e0 == pytest.approx(e_end + damper + released, rel=2e-4)


def _released(phases: list[tuple[float, str, float, float]]) -> float:
    """The spring energy at each end of pushing that leaves the contact still compressed."""
    total = 0.0
    for (_, kind, _, _), (_, nxt, p, _) in itertools.pairwise(phases):
        if kind == "contact" and nxt == "free":
            total += 0.5 * C * max(abs(p) - B_MAX, 0.0) ** 2
    return total


ELASTO_BACKLASH2_MO = """
model Backlash2Branch "The Backlash example's ElastoBacklash2 branch, as MSL writes it"
  import Modelica.Mechanics.Rotational;
  Rotational.Components.Fixed fixed3;
  Rotational.Components.ElastoBacklash2 elastoBacklash2(
    c=20E3,
    d=50,
    phi_nominal=1,
    b(displayUnit="deg") = 0.78539816339745);
  Rotational.Components.Inertia inertia3(
    J=5,
    w(fixed=true, start=0),
    phi(fixed=true, start=1.570796326794897, displayUnit="deg"));
equation
  connect(elastoBacklash2.flange_b, inertia3.flange_a);
  connect(fixed3.flange, elastoBacklash2.flange_a);
  annotation (experiment(StopTime=1.0, Interval=0.001));
end Backlash2Branch;
"""


def test_elasto_backlash2_imports_from_modelica_and_round_trips() -> None:
    model = st.Model.from_modelica(ELASTO_BACKLASH2_MO)
    assert st.Model.from_modelica(model.to_modelica()) == model
    r = model.simulate()
    phi, _ = exact(1.0)[1](r.time)
    assert np.abs(r["elastoBacklash2.phi_rel"] - phi).max() < 1e-4 * np.ptp(phi)


@pytest.mark.parametrize(("params", "name"), [({"b": -0.1}, "b"), ({"c": 0.0}, "c"), ({"d": -1.0}, "d")])
def test_elasto_backlash2_refuses_bad_parameters_by_name(params: dict, name: str) -> None:
    """Refused where the component is made, and by the engine from a model file."""
    with pytest.raises(st.ModelError, match=rf"ElastoBacklash2.*'{name}'"):
        st.ElastoBacklash2(**params)
    ((key, value),) = params.items()
    text = f"""
name = "bad"
connect = [["fixed.flange", "bl.flange_a"], ["bl.flange_b", "J.flange_a"]]
[components]
fixed = {{ type = "Fixed" }}
bl = {{ type = "ElastoBacklash2", {key} = {value} }}
J = {{ type = "Inertia", J = 1.0 }}
"""
    with pytest.raises(st.ModelError, match=rf"bl.*\b{name}\b"):
        st.Model.loads(text).simulate()
