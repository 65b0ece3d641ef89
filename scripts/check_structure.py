#!/usr/bin/env python3
"""Structural rules of the Rust crates, checked in CI (`make lint`).

1. Layers. The top-level modules of `crates/stiction-core/src` are declared in `LAYERS`, in
   their documented order from the bottom (docs/architecture.md, "Layers", says the same), and
   each imports only modules before it. A module missing from the list is an error too: a new
   one gets its place in the order (here and in the docs) when it is added.
2. Siblings. Within a folder of any crate, and among a crate's top-level modules, modules
   import one another without a cycle (a child using its parent `mod.rs` is fine).
3. One API surface. The core's modules are private (`mod x;` in lib.rs, never `pub mod`):
   everything outside it — stiction-py, stiction-fmi, the core's own integration tests and
   examples — reaches the core through the names lib.rs re-exports (`stiction_core::Name`),
   never `stiction_core::module::…`. Inside the core, code imports from a module
   (`crate::result::SimResult`), not a root re-export (`crate::SimResult`), so that rule 1
   sees every dependency.
4. Size, a warning only: a Rust file longer than 500 lines is printed as a smell to look at
   (is it one job?), not a failure — a file is split by job, never by length.

Imports are read from the source text: every `crate::a::b` path and every `super::x` path, in
`use` lines and in code alike, outside a file's unit tests (its `#[cfg(test)] mod tests` block
or a `tests.rs` file). Prints each violation and exits 1 if there is one.

    scripts/check_structure.py [--root DIR]

`--root` checks the crates under DIR instead of this repository (tests/test_check_structure.py
shows a wrong import fails).
"""

from __future__ import annotations

import argparse
import re
import sys
from collections import defaultdict
from collections.abc import Iterable
from pathlib import Path

# The core's top-level modules, from the bottom: each imports only modules before it.
LAYERS = [
    "error",  # the error types
    "linalg",  # linear solvers (dense, banded, refactoring) and the rank test
    "model",  # the model description: ModelSpec, Params, declarations
    "lookup_table",  # interpolation tables (MSL's CombiTable1D)
    "rel",  # node coordinates: rows over node angles
    "switching",  # stick/slip and quadrant logic: the SwitchingElement trait and its kinds
    "signals",  # the run-time signal network
    "thermal",  # the run-time thermal network
    "wear",  # pad wear of friction elements at run time
    "system",  # the assembled System and the Builder components contribute through
    "components",  # the component constructors
    "assembly",  # creating components, resolving the topology, building; CompiledModel
    "catalogue",  # every component type's parameters, ports and variables
    "engine",  # evaluation, per-mode solve, crossings, event iteration
    "result",  # the recorded run: variables, metrics, the table engine, result files
    "compare",  # the MSL tube comparison of a result against a reference (a test oracle)
    "simulation",  # the resumable run, its saved state and the state's bytes
    "start_report",  # the start-value report: fixed, guessed or computed
    "sweep",  # variants of a compiled model on threads
]

CORE = Path("crates") / "stiction-core"
MAX_LINES = 500
CRATE_PATH = re.compile(r"\bcrate::((?:\w+::)*\w+)")
SUPER_PATH = re.compile(r"\bsuper::(\w+)")
USE_GROUP = re.compile(r"\buse\s+(crate|super)::\{([^;]*)\};", re.DOTALL)
CORE_PATH = re.compile(r"\bstiction_core::(\w+)::")
CORE_GROUP = re.compile(r"\bstiction_core::\{([^;]*)\}", re.DOTALL)


def module_path(file: Path, src: Path) -> list[str]:
    """`engine/eval.rs` → ["engine", "eval"]; `engine/mod.rs` → ["engine"]."""
    parts = list(file.relative_to(src).with_suffix("").parts)
    if parts[-1] in ("mod", "lib"):
        parts = parts[:-1]
    return parts


def strip_comments(text: str) -> str:
    """The code without comments and without its unit tests (a file's `#[cfg(test)] mod tests`
    comes last; a test may drive the whole engine, which is not an import of the module)."""
    text = re.split(r"#\[cfg\(test\)\]\s*mod tests\b", text, maxsplit=1)[0]
    return "\n".join(line.split("//", 1)[0] for line in text.splitlines())


def is_test_file(file: Path) -> bool:
    """A unit-test module of its own (`#[cfg(test)] mod tests;` → tests.rs)."""
    return file.stem == "tests"


def referenced_paths(code: str, own: list[str], is_mod_file: bool) -> set[tuple[str, ...]]:
    """Absolute module paths this file refers to (each as far as it is written)."""
    paths: set[tuple[str, ...]] = set()
    parent = own if is_mod_file else own[:-1]  # what `super` means, relative to the file
    for match in CRATE_PATH.finditer(code):
        paths.add(tuple(match.group(1).split("::")))
    for match in SUPER_PATH.finditer(code):
        paths.add((*parent[:-1], match.group(1)) if is_mod_file else (*parent, match.group(1)))
    for kind, group in USE_GROUP.findall(code):  # `use crate::{a, b::c}`
        base: list[str] = [] if kind == "crate" else (parent[:-1] if is_mod_file else parent)
        for item in re.split(r"[,\s]+", group):
            name = item.split("::")[0].strip("{}")
            if re.fullmatch(r"\w+", name) and name != "self":
                paths.add((*base, name))
    return paths


def find_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one member (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                cycles.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return cycles


def crate_imports(
    src: Path,
) -> tuple[dict[str, set[str]], dict[tuple[str, ...], dict[str, set[str]]], set[str], list[str]]:
    """One crate's imports: between its top-level modules, between siblings of each folder;
    its top-level module names; and, for the core, uses of a root re-export inside it."""
    top: dict[str, set[str]] = defaultdict(set)
    siblings: dict[tuple[str, ...], dict[str, set[str]]] = defaultdict(lambda: defaultdict(set))
    files = sorted(src.rglob("*.rs"))
    modules = {tuple(module_path(f, src)) for f in files}
    tops = {m[0] for m in modules if m}
    through_root: list[str] = []
    for file in files:
        own = module_path(file, src)
        if is_test_file(file):
            continue
        code = strip_comments(file.read_text(encoding="utf-8"))
        for path in referenced_paths(code, own, file.name in ("mod.rs", "lib.rs")):
            if not path or not own:
                continue
            if path[0] != own[0] and (path[0],) in modules:
                top[own[0]].add(path[0])
            # sibling edges: the first point where the two paths part, if both are modules
            common = 0
            while common < min(len(own), len(path)) and own[common] == path[common]:
                common += 1
            if common < len(own) and common < len(path) and (*path[: common + 1],) in modules:
                folder = tuple(own[:common])
                siblings[folder][own[common]].add(path[common])
        for first in sorted({m.group(1).split("::")[0] for m in CRATE_PATH.finditer(code)} - tops):
            where = file.relative_to(src.parent.parent)
            through_root.append(f"{where}: crate::{first}, a root re-export (import it from its module)")
    return top, siblings, tops, through_root


def layer_problems(top: dict[str, set[str]], tops: set[str]) -> list[str]:
    problems = []
    rank = {m: i for i, m in enumerate(LAYERS)}
    for module in sorted(tops - set(rank)):
        problems.append(
            f"stiction-core: top-level module '{module}' has no place in the layer order "
            "(LAYERS in scripts/check_structure.py and docs/architecture.md's Layers)"
        )
    for module, deps in sorted(top.items()):
        for dep in sorted(deps):
            if module in rank and dep in rank and rank[dep] > rank[module]:
                problems.append(
                    f"stiction-core: {module} imports {dep}, a layer above it "
                    f"({' → '.join(LAYERS[rank[module] : rank[dep] + 1])})"
                )
    return problems


def public_modules(lib: Path) -> list[str]:
    """`pub mod` declarations in the core's lib.rs: every module is the crate's own."""
    code = strip_comments(lib.read_text(encoding="utf-8"))
    names = re.findall(r"^\s*pub(?:\([^)]*\))?\s+mod\s+(\w+)", code, flags=re.MULTILINE)
    return [
        f"{lib.parent.parent.name}/src/lib.rs: 'pub mod {n}' (modules are private; re-export names)"
        for n in names
    ]


def outside_users(root: Path) -> Iterable[Path]:
    """The Rust files that use the core from outside it."""
    crates = root / "crates"
    core = root / CORE
    for folder in ("tests", "examples", "benches"):
        yield from sorted((core / folder).rglob("*.rs"))
    for crate in sorted(p for p in crates.iterdir() if p.is_dir() and p != core):
        yield from sorted(crate.rglob("*.rs"))


def root_problems(root: Path, core_modules: set[str]) -> list[str]:
    """Paths into the core's modules from outside it (`stiction_core::module::…`)."""
    problems = []
    for file in outside_users(root):
        code = "\n".join(line.split("//", 1)[0] for line in file.read_text(encoding="utf-8").splitlines())
        used = {m.group(1) for m in CORE_PATH.finditer(code)}
        for group in CORE_GROUP.findall(code):  # `stiction_core::{simulation::X, Y}`
            used |= {item.split("::")[0] for item in re.split(r"[,\s]+", group) if "::" in item}
        for module in sorted(used & core_modules):
            problems.append(
                f"{file.relative_to(root)}: stiction_core::{module}::… (use the name lib.rs re-exports)"
            )
    return problems


def layers_in_docs(root: Path) -> list[str]:
    """docs/architecture.md lists the layers in the same order (when the file is there)."""
    doc = root / "docs" / "architecture.md"
    if not doc.exists():
        return []
    found = re.search(r"^Layer order, checked: (.*)$", doc.read_text(encoding="utf-8"), flags=re.MULTILINE)
    if not found:
        return ["docs/architecture.md: no line 'Layer order, checked: `error` ← `linalg` ← …'"]
    documented = re.findall(r"`(\w+)`", found.group(1))
    if documented != LAYERS:
        return [f"docs/architecture.md lists the layers as {documented}, the check as {LAYERS}"]
    return []


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", type=Path, default=Path(__file__).resolve().parents[1])
    root = parser.parse_args(argv).root.resolve()
    problems: list[str] = []
    warnings: list[str] = []
    summary = []
    core_modules: set[str] = set()
    for crate in sorted(p for p in (root / "crates").iterdir() if (p / "src").is_dir()):
        top, siblings, tops, through_root = crate_imports(crate / "src")
        if crate == root / CORE:
            core_modules = tops
            problems += layer_problems(top, tops)
            problems += public_modules(crate / "src" / "lib.rs")
            problems += through_root
            layers = ", ".join(f"{m} → {{{', '.join(sorted(d))}}}" for m, d in sorted(top.items()))
            summary.append(f"core imports: {layers}")
        for cycle in find_cycles(top):
            problems.append(f"{crate.name}: import cycle between top-level modules: {' ↔ '.join(cycle)}")
        for folder, graph in siblings.items():
            if not folder:
                continue  # the top level is checked above
            for cycle in find_cycles(graph):
                where = "::".join(folder)
                problems.append(
                    f"{crate.name}: import cycle among the modules of {where}: {' ↔ '.join(cycle)}"
                )
    problems += root_problems(root, core_modules)
    problems += layers_in_docs(root)
    for file in sorted((root / "crates").rglob("*.rs")):
        lines = len(file.read_text(encoding="utf-8").splitlines())
        if lines > MAX_LINES:
            warnings.append(f"{file.relative_to(root)}: {lines} lines (a smell to look at: one job?)")
    for warning in warnings:
        print(f"warning: {warning}")
    for problem in problems:
        print(problem)
    print(f"structure: {len(list((root / 'crates').rglob('*.rs')))} files; {'; '.join(summary)}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
