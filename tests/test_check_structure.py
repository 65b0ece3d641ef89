"""The Rust crates' structure check (scripts/check_structure.py, run by `make lint`) passes on
the repository and fails on a deliberately wrong import: a layer importing one above it, a
binding reaching into a core module, a public core module, a module with no place in the
order. A long file is a warning, not a failure."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "scripts" / "check_structure.py"


def check(root: Path | None = None) -> subprocess.CompletedProcess[str]:
    args = [sys.executable, str(SCRIPT)] + (["--root", str(root)] if root else [])
    return subprocess.run(args, capture_output=True, text=True, check=False)


def write(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    return root


# A tiny tree that keeps the rules: three layers of the core, a binding using its root.
GOOD = {
    "crates/stiction-core/src/lib.rs": "mod error;\nmod model;\nmod simulation;\n\npub use simulation::simulate;\n",
    "crates/stiction-core/src/error.rs": "pub struct ModelError;\n",
    "crates/stiction-core/src/model/mod.rs": "mod spec;\npub use spec::ModelSpec;\n",
    "crates/stiction-core/src/model/spec.rs": "use crate::error::ModelError;\npub struct ModelSpec;\n",
    "crates/stiction-core/src/simulation.rs": "use crate::model::ModelSpec;\npub fn simulate(_: &ModelSpec) {}\n",
    "crates/stiction-core/tests/run.rs": "use stiction_core::simulate;\n",
    "crates/stiction-py/src/lib.rs": "use stiction_core::{simulate, ModelSpec};\n",
}


def test_the_repository_passes() -> None:
    done = check()
    assert done.returncode == 0, done.stdout + done.stderr


def test_a_tree_that_keeps_the_rules_passes(tmp_path: Path) -> None:
    done = check(write(tmp_path, GOOD))
    assert done.returncode == 0, done.stdout + done.stderr


def test_a_layer_importing_one_above_it_fails(tmp_path: Path) -> None:
    wrong = {
        **GOOD,
        "crates/stiction-core/src/error.rs": "use crate::model::ModelSpec;\npub struct ModelError;\n",
    }
    done = check(write(tmp_path, wrong))
    assert done.returncode == 1
    assert "error imports model, a layer above it" in done.stdout


def test_a_binding_reaching_into_a_core_module_fails(tmp_path: Path) -> None:
    users = ("crates/stiction-py/src/lib.rs", "crates/stiction-core/tests/run.rs")
    lines = (
        "use stiction_core::simulation::simulate;\n",
        "use stiction_core::{model::ModelSpec, simulate};\n",
    )
    for i, (user, line) in enumerate((u, l) for u in users for l in lines):
        with_line = {**GOOD, user: line}
        done = check(write(tmp_path / str(i), with_line))
        assert done.returncode == 1, (user, line)
        assert "use the name lib.rs re-exports" in done.stdout


def test_a_public_module_an_unplaced_module_and_a_root_import_inside_fail(tmp_path: Path) -> None:
    lib = GOOD["crates/stiction-core/src/lib.rs"]
    cases = {
        "pub mod": {"crates/stiction-core/src/lib.rs": lib.replace("mod model;", "pub mod model;")},
        "no place in the layer order": {
            "crates/stiction-core/src/lib.rs": lib + "mod helpers;\n",
            "crates/stiction-core/src/helpers.rs": "",
        },
        "a root re-export": {
            "crates/stiction-core/src/simulation.rs": "use crate::ModelSpec;\npub fn simulate(_: &ModelSpec) {}\n"
        },
    }
    for i, (message, files) in enumerate(cases.items()):
        done = check(write(tmp_path / str(i), {**GOOD, **files}))
        assert done.returncode == 1, message
        assert message in done.stdout


def test_a_long_file_is_a_warning_not_a_failure(tmp_path: Path) -> None:
    long = "pub struct ModelError;\n" + "// a line\n" * 600
    done = check(write(tmp_path, {**GOOD, "crates/stiction-core/src/error.rs": long}))
    assert done.returncode == 0, done.stdout
    assert "warning: crates/stiction-core/src/error.rs: 601 lines" in done.stdout


def test_docs_listing_another_order_fail(tmp_path: Path) -> None:
    docs = {"docs/architecture.md": "## Layers\n\nLayer order, checked: `model` ← `error`\n"}
    done = check(write(tmp_path, {**GOOD, **docs}))
    assert done.returncode == 1
    assert "docs/architecture.md lists the layers as ['model', 'error']" in done.stdout


def test_an_import_loop_in_another_crate_fails(tmp_path: Path) -> None:
    fmi = {
        "crates/stiction-fmi/src/lib.rs": "mod instance;\nmod serial;\n",
        "crates/stiction-fmi/src/instance.rs": "use crate::serial::to_bytes;\npub struct Snapshot;\n",
        "crates/stiction-fmi/src/serial.rs": "use crate::instance::Snapshot;\npub fn to_bytes() {}\n",
    }
    done = check(write(tmp_path, {**GOOD, **fmi}))
    assert done.returncode == 1
    assert "stiction-fmi: import cycle between top-level modules: instance ↔ serial" in done.stdout
