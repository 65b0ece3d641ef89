"""The README's code runs as written (issue 29: its comment said ``print(r.events[1])`` shows the
lock at 0.9 s; it showed the brake's engagement at 0.5 s). Each ``python`` block runs in order
in one namespace, as a reader pastes them; a line ``print(x)  # text`` must print ``text`` (a
trailing ``(…)`` stands for the rest of the line); the model file example loads."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest
from paths import EXAMPLES, REPO

import stiction as st

README = REPO / "README.md"
PRINTED = re.compile(r"^print\((?P<value>.*)\)\s*#\s*(?P<expected>.*)$")


def blocks(language: str) -> list[str]:
    """The README's fenced blocks of one language, in order."""
    return re.findall(
        rf"^```{language}\n(.*?)^```", README.read_text(encoding="utf-8"), re.MULTILINE | re.DOTALL
    )


def with_print_checks(code: str) -> str:
    """``print(x)  # text`` lines turned into a check that ``str(x)`` reads ``text``."""
    lines = []
    for line in code.splitlines():
        m = PRINTED.match(line)
        if m:
            expected = m.group("expected").removesuffix("(…)").rstrip()
            line = f"_printed_as({m.group('value')}, {expected!r})"
        lines.append(line)
    return "\n".join(lines)


def printed_as(value: object, expected: str) -> None:
    shown = str(value)
    assert shown.startswith(expected), f"the README says {expected!r}, the code prints {shown!r}"


def test_there_are_blocks_to_run() -> None:
    assert len(blocks("python")) >= 3
    assert any(PRINTED.match(line) for b in blocks("python") for line in b.splitlines())


@pytest.mark.filterwarnings("ignore")
def test_the_python_blocks_run_as_written(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "examples").symlink_to(EXAMPLES, target_is_directory=True)
    monkeypatch.chdir(tmp_path)  # the blocks write out.csv, out.png … here
    monkeypatch.setattr(sys, "argv", ["README"])
    namespace: dict[str, object] = {"_printed_as": printed_as}
    for number, code in enumerate(blocks("python"), start=1):
        exec(compile(with_print_checks(code), f"README.md python block {number}", "exec"), namespace)  # noqa: S102
    assert (tmp_path / "out.csv").is_file() and (tmp_path / "BrakedFlywheel.mo").is_file()


def test_the_model_file_example_loads_and_runs() -> None:
    (text,) = blocks("toml")
    result = st.Model.loads(text).simulate()
    assert result.first("brake.locked") is not None
