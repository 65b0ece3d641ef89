"""A plain model file loads as the engine's compile of it, its Python objects made when first
read (issue 34; stiction/model/loaded.py). Whatever a user does with such a model must be what
a model built in Python does: the same run, the same objects, the same errors at load."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest

from stiction.errors import ModelError
from stiction.model import modelfile
from stiction.model.components import Component
from stiction.model.model import Model
from stiction.testing import ladder_toml


def _file(tmp_path: Path, text: str, name: str = "ladder.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _built(text: str) -> Model:
    """The model of ``text`` made through the API, component by component."""
    data = modelfile.parse(text)
    model = Model(data.name or "model")
    model.experiment.update(data.experiment)
    for name, kind, params in data.components:
        model.add(name, Component(kind, params))
    for a, b in data.connections:
        model.connect(a, b)
    return model


def _same_runs(a, b) -> None:
    assert a.names == b.names
    np.testing.assert_array_equal(a.data, b.data)


def test_a_plain_file_runs_untouched_as_the_model_built_in_python(tmp_path: Path) -> None:
    text = ladder_toml(12)
    loaded = Model.load(_file(tmp_path, text))
    assert loaded._lazy is not None  # nothing made at load …
    run = loaded.simulate()
    assert loaded._lazy is not None  # … nor by the run
    built = _built(text)
    _same_runs(run, built.simulate())
    assert run.parameters == built.parameter_values()
    assert run.unit("J3.w") == "rad/s"
    assert loaded == built  # made now, and equal
    assert loaded._lazy is None


def test_the_objects_are_those_a_python_load_makes(tmp_path: Path) -> None:
    text = ladder_toml(8)
    loaded = Model.load(_file(tmp_path, text))
    shown = repr(loaded)  # the counts, without making anything
    assert loaded._lazy is not None
    eager = Model._from_data(modelfile.parse(text), tmp_path, "ladder")
    assert shown == repr(eager)
    assert loaded.connections == eager.connections
    assert loaded.components == eager.components
    assert loaded.types() == eager.types()
    assert loaded.to_toml() == eager.to_toml()


def test_a_change_after_touching_the_components_is_run(tmp_path: Path) -> None:
    path = _file(tmp_path, ladder_toml(8))
    before = Model.load(path).simulate()["J7.w"]
    model = Model.load(path)
    model.components["clutch1"].params["fn_max"] = 0.5  # in place, on the objects made now
    changed = model.simulate()["J7.w"]
    assert not np.array_equal(before, changed)
    again = Model.load(path)
    again.set("clutch1.fn_max", 0.5)
    np.testing.assert_array_equal(again.simulate()["J7.w"], changed)


def test_a_result_keeps_its_run_parameters_when_the_model_changes(tmp_path: Path) -> None:
    model = Model.load(_file(tmp_path, ladder_toml(8)))
    run = model.simulate()
    model.set("J1.J", 2.5)
    assert run.parameters["J1.J"] == 1.0
    assert model.simulate().parameters["J1.J"] == 2.5


def test_an_attribute_set_before_anything_is_made_is_kept(tmp_path: Path) -> None:
    model = Model.load(_file(tmp_path, ladder_toml(8)))
    model.experiment = {"StopTime": 0.2, "Interval": 0.01}
    run = model.simulate()
    assert run["time"][-1] == pytest.approx(0.2)
    assert len(model.components) == len(modelfile.parse(ladder_toml(8)).components)  # made from the file


def test_a_renamed_model_runs_under_its_new_name(tmp_path: Path) -> None:
    model = Model.load(_file(tmp_path, ladder_toml(8)))
    model.name = "Renamed"
    assert model.engine_toml().startswith('format = 1\nname = "Renamed"')
    assert model.simulate().name == "Renamed"


def test_overrides_of_a_loaded_model(tmp_path: Path) -> None:
    text = ladder_toml(8)
    loaded = Model.load(_file(tmp_path, text))
    numbers = {"clutch1.fn_max": 5.0, "J2.w": 3}
    short = loaded.simulate(StopTime=0.3, params=numbers)
    assert loaded._lazy is not None  # numbers need nothing made
    assert short["time"][-1] == pytest.approx(0.3)
    _same_runs(short, _built(text).simulate(StopTime=0.3, params=numbers))
    assert short.parameters == _built(text).parameter_values()  # the model's, as before
    quantity = loaded.simulate(StopTime=0.3, params={**numbers, "J2.w": "3 rad/s"})
    assert loaded._lazy is None  # a unit to convert: the objects made
    _same_runs(quantity, short)
    with pytest.raises(ModelError, match=r"component 'clutch1' \(Clutch\): parameter 'fn_mx': unknown"):
        Model.load(_file(tmp_path, text)).simulate(params={"clutch1.fn_mx": 5.0})


def test_pickles_of_a_loaded_model(tmp_path: Path) -> None:
    path = _file(tmp_path, ladder_toml(8))
    copy = pickle.loads(pickle.dumps(Model.load(path)))
    assert copy._lazy is None and copy == Model.load(path)
    _same_runs(copy.simulate(), Model.load(path).simulate())


@pytest.mark.parametrize(
    ("extra", "plain"),
    [
        ("", True),
        ("\n[parameters]\nk = 2.0\n", False),  # top-level parameters: built in Python
        ('\n[components.t]\ntype = "TimeTable"\ntable = [[0.0, 1.0], [1.0, 2.0]]\n', False),
    ],
)
def test_only_plain_files_load_lazily(tmp_path: Path, extra: str, plain: bool) -> None:
    model = Model.load(_file(tmp_path, ladder_toml(4) + extra))
    assert (model._lazy is not None) is plain


_PAIR = 'a = { type = "Inertia", J = 1.0 }\nb = { type = "Inertia", J = 1.0 }\n'


@pytest.mark.parametrize(
    ("connect", "components", "message"),
    [
        # the engine takes these two; Python refuses them at load, and still does
        ('["a.flange_b", "b.flange_a"], ["b.flange_a", "a.flange_b"]', _PAIR, "already connected"),
        ('["a.flange_b", "a.flange_b"]', _PAIR, "a port cannot be connected to itself"),
        (
            "",
            'a = { type = "Inertia", J = -1.0 }\n',
            r"component 'a' \(Inertia\): parameter 'J': must be >= 0",
        ),
        (
            "",
            'a = { type = "Inertia", Jx = 1.0 }\n',
            r"parameter 'Jx': unknown parameter \(did you mean 'J'\?\)",
        ),
        ("", 'a = { type = "Inertiax", J = 1.0 }\n', r"unknown component type \(did you mean 'Inertia'\?\)"),
        ('["a.flange_c", "b.flange_a"]', _PAIR, r"port 'flange_c': unknown port"),
        (
            '["a.flange_b", "m.flange_a"]',
            'a = { type = "Inertia", J = 1.0 }\nm = { type = "Translational.Mass", m = 1.0 }\n',
            "cannot connect the rotational flange 'a.flange_b' to the translational",
        ),
        ("", '"J-1" = { type = "Inertia", J = 1.0 }\n', "component name 'J-1' is not a valid identifier"),
        ("", 'a = { type = "Inertia", "" = 1.0 }\n', "parameter names must be non-empty strings"),
        ("", 'a = { type = "Inertia", J = nan }\n', "parameter 'J': must be >= 0, got nan"),
    ],
)
def test_bad_plain_files_are_refused_at_load_in_python_words(
    tmp_path: Path, connect: str, components: str, message: str
) -> None:
    text = f'name = "bad"\nconnect = [{connect}]\n\n[components]\n{components}'
    with pytest.raises(ModelError, match=message):
        Model.load(_file(tmp_path, text, "bad.toml"))
