"""A model loaded from a file and run unchanged hands the engine the file's own text (issue
34: writing it back was a fifth of the Python time of a big model); any change to the model
is run as changed, and a file the engine text would spell otherwise is written as before."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from stiction.model.model import Model
from stiction.testing import chain_toml


def _written(model: Model) -> str:
    """The engine text as writing the model gives it."""
    return model._write_engine_toml()


def test_an_unchanged_file_runs_as_its_own_text_and_as_the_written_model(tmp_path: Path) -> None:
    path = tmp_path / "chain.toml"
    path.write_text(chain_toml(4), encoding="utf-8")
    loaded = Model.load(path)
    assert loaded.engine_toml() == path.read_text(encoding="utf-8")
    assert loaded._parsed is not None  # the engine's reading of the load's parse …
    written = Model.loads(_written(loaded))  # the same model through the written text
    assert written.engine_toml() == _written(loaded)
    a, b = loaded.simulate(), written.simulate()
    assert loaded._parsed is None  # … taken by the compile
    for name in ("J4.w", "J1.phi", "J2.w"):
        np.testing.assert_array_equal(a[name], b[name])


def test_a_file_without_a_name_is_named_for_the_engine(tmp_path: Path) -> None:
    text = chain_toml(2).replace('name = "', 'title_was = "').split("\n", 1)[1]
    path = tmp_path / "unnamed.toml"
    path.write_text(text, encoding="utf-8")
    model = Model.load(path)
    assert model.name == "unnamed"
    assert model.engine_toml() == f'name = "unnamed"\n{text}'
    assert model.compile()._core.parameter_names()  # the engine reads it


@pytest.mark.parametrize(
    "change",
    [
        lambda m: m.set("clutch1.fn_max", 5.0),
        lambda m: m.components["clutch1"].params.__setitem__("fn_max", 5.0),  # in place
        lambda m: m.experiment.__setitem__("StopTime", 0.1),
    ],
)
def test_a_loaded_model_changed_runs_the_change(tmp_path: Path, change) -> None:
    path = tmp_path / "chain.toml"
    path.write_text(chain_toml(3), encoding="utf-8")
    model = Model.load(path)
    before = model.simulate()["J3.w"]
    change(model)
    assert model.engine_toml() == _written(model)
    after = model.simulate()["J3.w"]
    assert len(after) != len(before) or not np.array_equal(after, before)


def test_a_file_spelling_values_otherwise_is_written(tmp_path: Path) -> None:
    # "20 N" is converted to 20.0 when read, an integer J stays what the file says only if the
    # component holds it so: the engine gets the model's values, as before
    text = chain_toml(2).replace("fn_max = 20.0", 'fn_max = "20 N"')
    path = tmp_path / "units.toml"
    path.write_text(text, encoding="utf-8")
    model = Model.load(path)
    assert model.engine_toml() == _written(model)
    assert "fn_max = 20.0" in model.engine_toml()


def test_top_level_parameters_are_evaluated_as_before(tmp_path: Path) -> None:
    text = chain_toml(2).replace("fn_max = 20.0", 'fn_max = { expr = "F" }') + "\n[parameters]\nF = 20.0\n"
    path = tmp_path / "params.toml"
    path.write_text(text, encoding="utf-8")
    model = Model.load(path)
    assert model.engine_toml() == _written(model)
    assert "expr" not in model.engine_toml()


def test_an_engine_refusal_comes_at_the_run_as_before(tmp_path: Path) -> None:
    from stiction.errors import ModelError

    text = chain_toml(2).replace("Tolerance = 1e-6", "Tolerance = -1.0")
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    model = Model.load(path)  # the engine refuses it: no reading kept, its text compile says why
    with pytest.raises(ModelError, match="Tolerance"):
        model.simulate()


def test_the_compile_begun_at_load_raises_at_the_run_as_the_text_compile(tmp_path: Path) -> None:
    from stiction.errors import ModelError
    from stiction.run.compiled import CompiledModel

    lines = chain_toml(2).splitlines()
    text = "\n".join(line for line in lines if "clutch1.f_normalized" not in line) + "\n"
    path = tmp_path / "open.toml"
    path.write_text(text, encoding="utf-8")
    model = Model.load(path)  # Python's checks pass; the engine refuses the open input
    assert model._parsed is not None
    with pytest.raises(ModelError) as from_text:
        CompiledModel(text, tmp_path)
    with pytest.raises(ModelError) as at_run:
        model.simulate()
    assert str(at_run.value) == str(from_text.value)
    assert "clutch1" in str(at_run.value)


def test_a_file_with_a_date_is_read_by_tomllib_and_refused_by_name(tmp_path: Path) -> None:
    # the engine's reading takes any value; the Python objects of a date come from tomllib
    from stiction.errors import ModelError

    text = chain_toml(1).replace('"Inertia", J = 1.0,', '"Inertia", J = 1.0, when = 2026-12-06,', 1)
    path = tmp_path / "dated.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ModelError, match="parameter 'when'"):
        Model.load(path)
