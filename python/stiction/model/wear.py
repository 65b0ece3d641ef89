"""Wear models for the friction elements' ``wear`` parameter (a stiction extension of MSL):
``st.Brake(fn_max=4000.0, wear=st.wear.Energy(alpha=2e-13))``. Each is a read-only mapping —
the record a TOML model writes as ``wear = { model = "energy", alpha = 2e-13 }`` — so a plain
dict works as well. The engine checks the values when it reads the model (docs/wear.md)."""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from typing import Any, ClassVar

__all__ = ["Archard", "Arrhenius", "Energy", "WearModel"]


class WearModel(Mapping[str, Any]):
    """Base of the wear models: the record ``{"model": …, constants…}``. The optional pad
    values are common to all: ``A`` [m2] and ``thickness`` [m] (then ``<element>.thickness`` is
    reported), ``thickness_min`` [m] (the run stops with ``WearLimitError`` when the pad wears
    down to it) and ``nominal`` [m3] (the volume scale of the error control)."""

    model: ClassVar[str]

    def __init__(self, **values: float | None) -> None:
        self._values: dict[str, Any] = {"model": self.model}
        self._values.update({k: float(v) for k, v in values.items() if v is not None})

    def __getitem__(self, key: str) -> Any:
        return self._values[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self._values.items() if k != "model")
        return f"st.wear.{type(self).__name__}({args})"


class Archard(WearModel):
    """Archard's law: worn volume rate ``k·fn·v_slide/H`` with ``v_slide = r_eff·|w_rel|``
    (translational: ``|v_rel|``, no ``r_eff``); ``k`` the dimensionless wear coefficient, ``H``
    [Pa] the hardness of the softer body, ``r_eff`` [m] the effective friction radius."""

    model = "archard"

    def __init__(
        self,
        *,
        k: float,
        H: float,  # the law's name for the hardness
        r_eff: float | None = None,
        A: float | None = None,  # the pad's area, as the TOML record names it
        thickness: float | None = None,
        thickness_min: float | None = None,
        nominal: float | None = None,
    ) -> None:
        super().__init__(
            k=k, H=H, r_eff=r_eff, A=A, thickness=thickness, thickness_min=thickness_min, nominal=nominal
        )


class Energy(WearModel):
    """Energy (frictional work) wear: worn volume rate ``alpha·lossPower``, ``alpha`` [m3/J]."""

    model = "energy"

    def __init__(
        self,
        *,
        alpha: float,
        A: float | None = None,
        thickness: float | None = None,
        thickness_min: float | None = None,
        nominal: float | None = None,
    ) -> None:
        super().__init__(alpha=alpha, A=A, thickness=thickness, thickness_min=thickness_min, nominal=nominal)


class Arrhenius(WearModel):
    """Thermal wear: rate ``lossPower·(alpha0 + k0·max(0, exp(−E/(R·T)) − exp(−E/(R·T_threshold))))``
    with T the heat port's temperature [K] (the element needs ``useHeatPort = true`` and its port
    on a HeatCapacitor or a FixedTemperature); the energy law ``alpha0`` [m3/J] below
    ``T_threshold`` [K], an Arrhenius term (``k0`` [m3/J], activation energy ``E`` [J/mol])
    growing above it."""

    model = "arrhenius"

    def __init__(
        self,
        *,
        k0: float,
        E: float,  # the activation energy, as the law writes it
        T_threshold: float,
        alpha0: float = 0.0,
        A: float | None = None,
        thickness: float | None = None,
        thickness_min: float | None = None,
        nominal: float | None = None,
    ) -> None:
        super().__init__(
            alpha0=alpha0,
            k0=k0,
            E=E,
            T_threshold=T_threshold,
            A=A,
            thickness=thickness,
            thickness_min=thickness_min,
            nominal=nominal,
        )
