"""Finished sweep rows as Parquet parts in a folder, so an interrupted sweep resumes."""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from stiction import _deps
from stiction.errors import ModelError

if TYPE_CHECKING:
    import pandas

    from stiction.run.compiled import CompiledModel
    from stiction.sweeps.result import SweepTable


__all__ = ["PartStore"]


class PartStore:
    """Finished rows as Parquet parts in a folder, with a manifest naming the sweep."""

    def __init__(
        self,
        out: str | os.PathLike[str],
        compiled: CompiledModel,
        frame: pandas.DataFrame,
        metrics: list[str],
        outputs: list[str],
    ) -> None:
        self.dir = Path(out)
        self.dir.mkdir(parents=True, exist_ok=True)
        self.metrics, self.outputs = metrics, outputs
        digest = hashlib.sha256()
        digest.update(compiled.text.encode())
        digest.update(frame.to_json().encode())
        digest.update(json.dumps([metrics, outputs]).encode())
        manifest = {
            "sweep": digest.hexdigest(),
            "variants": len(frame),
            "metrics": metrics,
            "outputs": outputs,
        }
        path = self.dir / "sweep.json"
        if path.exists() and json.loads(path.read_text())["sweep"] != manifest["sweep"]:
            raise ModelError(
                f"{self.dir} holds the parts of another sweep (model, variants or metrics differ)"
            )
        path.write_text(json.dumps(manifest, indent=1))

    def load(self, table: SweepTable) -> None:
        """Enter the rows of the parts written so far into ``table``."""
        pq = _deps.parquet

        for part in sorted(self.dir.glob("part-*.parquet")):
            t = pq.read_table(part)
            rows = t.column("variant").to_numpy()
            values = np.column_stack([t.column(m).to_numpy() for m in self.metrics]).reshape(len(rows), -1)
            trajectories = [
                np.array(t.column(f"trajectory:{o}").to_pylist(), dtype=float) for o in self.outputs
            ]
            table.fill(
                rows, (values, trajectories, t.column("error").to_pylist(), t.column("wall_s").to_numpy())
            )

    def write(self, indices: np.ndarray, part: Any) -> None:
        """Write one finished batch (atomically: a part is whole or absent)."""
        pa = _deps.pyarrow
        pq = _deps.parquet

        values, trajectories, status, wall = part
        columns: dict[str, Any] = {"variant": indices}
        for m, name in enumerate(self.metrics):
            columns[name] = values[:, m]
        columns["error"] = list(status)
        columns["wall_s"] = wall
        for o, name in enumerate(self.outputs):
            columns[f"trajectory:{name}"] = [list(row) for row in trajectories[o]]
        path = self.dir / f"part-{int(indices[0]):09d}.parquet"
        tmp = path.with_suffix(".tmp")
        pq.write_table(pa.table(columns), tmp)
        tmp.replace(path)
