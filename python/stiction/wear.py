"""``st.wear``: the wear models a friction element's ``wear=`` takes (``st.wear.Archard``,
``st.wear.Energy``, ``st.wear.Arrhenius``); defined in ``stiction.model.wear``."""

from __future__ import annotations

from stiction.model.wear import Archard, Arrhenius, Energy, WearModel

__all__ = ["Archard", "Arrhenius", "Energy", "WearModel"]
