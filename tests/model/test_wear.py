"""Pad wear from Python (issue 32): ``st.wear.*`` as a friction element's ``wear=``, the worn
volume of a constant-mu stop against its closed form (energy: alpha·J·w0²/2; translational
Archard: k·fn·distance/H), ``WearLimitError`` at the pad's limit, bad records refused by name
before any run, the ``.mo`` round trip (stiction's annotation) and the result files."""

from __future__ import annotations

from pathlib import Path

import pytest

import stiction as st
from stiction.model.wear import Archard, Arrhenius, Energy

J, W0, MU, FN, CGEO = 2.0, 30.0, 0.4, 1500.0, 0.2  # stops at J·w0/(mu·cgeo·fn) = 0.5 s


def _stop(wear: object, stop_time: float = 1.0) -> st.Model:
    m = st.Model("stop")
    m.add("J1", st.Inertia(J=J, phi=0.0, w=W0))
    m.add("brake", st.Brake(fn_max=FN, cgeo=CGEO, mu_pos=[[0, MU]], wear=wear))
    m.add("press", st.Constant(k=1.0))
    m.connect("J1.flange_b", "brake.flange_a")
    m.connect("press.y", "brake.f_normalized")
    m.experiment.update(StopTime=stop_time, Interval=0.01, Tolerance=1e-8)
    return m


def test_the_wear_classes_are_the_records_a_model_file_writes() -> None:
    assert dict(st.wear.Energy(alpha=2e-13)) == {"model": "energy", "alpha": 2e-13}
    assert dict(Archard(k=1e-4, H=3e8, r_eff=0.1)) == {"model": "archard", "k": 1e-4, "H": 3e8, "r_eff": 0.1}
    assert Arrhenius(k0=1e-9, E=5e4, T_threshold=550)["alpha0"] == 0.0
    assert st.wear.Energy is Energy
    assert repr(Energy(alpha=1.0, A=2.0)) == "st.wear.Energy(alpha=1.0, A=2.0)"


def test_energy_wear_of_a_stop_and_the_thickness_left() -> None:
    alpha, area, h0 = 3e-13, 1e-3, 0.01
    r = _stop(Energy(alpha=alpha, A=area, thickness=h0)).simulate()
    volume = alpha * J * W0**2 / 2
    assert r["brake.wearVolume"][-1] == pytest.approx(volume, rel=1e-10)
    assert r["brake.thickness"][-1] == pytest.approx(h0 - volume / area, rel=1e-12)
    assert (r.unit("brake.wearVolume"), r.unit("brake.thickness")) == ("m3", "m")
    audit = r.audit()
    assert audit.ok(), audit.worst


def test_translational_archard_wear_is_k_fn_times_the_braking_distance_over_h() -> None:
    m_block, v0, mu, g, k, h = 1200.0, 7.5, 0.8, 9.81, 3e-4, 2e8
    m = st.Model("block")
    m.add("block", st.translational.Mass(m=m_block, s=0.0, v=v0))
    m.add("road", st.translational.Brake(fn_max=m_block * g, mu_pos=[[0, mu]], wear=Archard(k=k, H=h)))
    m.add("press", st.Constant(k=1.0))
    m.connect("block.flange_b", "road.flange_a")
    m.connect("press.y", "road.f_normalized")
    m.experiment.update(StopTime=2.0, Tolerance=1e-10)
    r = m.simulate()
    distance = v0**2 / (2 * mu * g)
    assert r["road.wearVolume"][-1] == pytest.approx(k * m_block * g * distance / h, rel=1e-10)


def test_the_pad_limit_raises_wear_limit_error_naming_the_element() -> None:
    alpha, area, h0, h_min = 1e-9, 1e-3, 0.012, 0.0115
    limit = area * (h0 - h_min)
    w_star = (W0**2 - 2 * limit / (alpha * J)) ** 0.5
    t_star = (W0 - w_star) / (MU * CGEO * FN / J)
    with pytest.raises(st.WearLimitError, match=r"'brake'.*thickness_min") as info:
        _stop(Energy(alpha=alpha, A=area, thickness=h0, thickness_min=h_min)).simulate()
    time = float(str(info.value).split("at t = ")[1].split(":")[0])
    assert time == pytest.approx(t_star, rel=1e-9)


@pytest.mark.parametrize(
    ("wear", "words"),
    [
        ({"model": "magic"}, 'unknown model "magic"'),
        ({"model": "archard", "k": -1.0, "H": 1e8, "r_eff": 0.1}, "'k' must be >= 0"),
        ({"model": "archard", "k": 1e-4, "r_eff": 0.1}, "needs 'H'"),
        (Arrhenius(k0=1e-9, E=5e4, T_threshold=500.0), "useHeatPort"),
    ],
)
def test_bad_wear_records_are_refused_by_name(wear: object, words: str) -> None:
    with pytest.raises(st.ModelError, match=f"brake.*wear.*{words}"):
        _stop(wear).compile()


def test_the_wear_record_round_trips_through_modelica(tmp_path: Path) -> None:
    m = _stop(Archard(k=2e-4, H=3e8, r_eff=0.15, A=4e-3, thickness=0.011))
    text = m.to_modelica()
    assert 'annotation(__stiction_wear(kind="archard"' in text
    back = st.Model.from_modelica(text)
    assert back.components["brake"].params["wear"] == dict(m.components["brake"].params["wear"])
    a, b = m.simulate(), back.simulate()
    assert b["brake.wearVolume"][-1] == a["brake.wearVolume"][-1]
    for suffix in (".csv", ".mat", ".parquet"):
        path = tmp_path / f"stop{suffix}"
        a.save(path)
        loaded = st.Result.load(path)
        assert loaded["brake.wearVolume"][-1] == pytest.approx(a["brake.wearVolume"][-1], rel=1e-12)
        assert loaded["brake.thickness"][-1] == pytest.approx(a["brake.thickness"][-1], rel=1e-12)


def test_a_running_simulation_carries_the_wear_across_advances_and_a_restored_state() -> None:
    """What a dynamometer schedule relies on: one Simulation, advanced and restored."""
    alpha = 3e-13
    sim = _stop(Energy(alpha=alpha)).simulation()
    sim.advance_to(0.3)
    w = W0 - MU * CGEO * FN / J * 0.3
    assert sim.get("brake.wearVolume") == pytest.approx(alpha * J * (W0**2 - w**2) / 2, rel=1e-10)
    saved = sim.state()
    sim.advance_to(1.0)
    end = sim.get("brake.wearVolume")
    assert end == pytest.approx(alpha * J * W0**2 / 2, rel=1e-10)
    sim.set_state(saved)
    sim.advance_to(1.0)
    assert sim.get("brake.wearVolume") == end
