#!/usr/bin/env python3
"""Structural rules of the Rust core, checked in CI (`make lint`).

1. The top-level modules of `crates/stiction-core/src` import one another without a cycle
   (layers import only downward).
2. Within a folder, sibling modules import one another without a cycle (a child using its
   parent `mod.rs` is fine).
3. No Rust file under `crates/` is longer than 500 lines.

Imports are read from the source text: every `crate::a::b` path and every `super::x` path,
in `use` lines and in code alike, outside a file's unit-test module. Prints each violation and exits 1 if there is one.
"""

from __future__ import annotations

import re
import sys
from collections import defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CORE = ROOT / "crates" / "stiction-core" / "src"
MAX_LINES = 500
CRATE_PATH = re.compile(r"\bcrate::((?:\w+::)*\w+)")
SUPER_PATH = re.compile(r"\bsuper::(\w+)")
USE_GROUP = re.compile(r"\buse\s+(crate|super)::\{([^;]*)\};", re.DOTALL)


def module_path(file: Path) -> list[str]:
    """`engine/eval.rs` → ["engine", "eval"]; `engine/mod.rs` → ["engine"]."""
    parts = list(file.relative_to(CORE).with_suffix("").parts)
    if parts[-1] in ("mod", "lib"):
        parts = parts[:-1]
    return parts


def strip_comments(text: str) -> str:
    """The code without comments and without its unit tests (a file's `#[cfg(test)] mod tests`
    comes last; a test may drive the whole engine, which is not an import of the module)."""
    text = re.split(r"#\[cfg\(test\)\]\s*mod tests\b", text, maxsplit=1)[0]
    return "\n".join(line.split("//", 1)[0] for line in text.splitlines())


def referenced_paths(text: str, own: list[str], is_mod_file: bool) -> set[tuple[str, ...]]:
    """Absolute module paths this file refers to (each as far as it is written)."""
    code = strip_comments(text)
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


def main() -> int:
    problems: list[str] = []
    top: dict[str, set[str]] = defaultdict(set)
    siblings: dict[tuple[str, ...], dict[str, set[str]]] = defaultdict(lambda: defaultdict(set))
    files = sorted(CORE.rglob("*.rs"))
    modules = {tuple(module_path(f)) for f in files}
    for file in files:
        own = module_path(file)
        text = file.read_text(encoding="utf-8")
        paths = referenced_paths(text, own, file.name in ("mod.rs", "lib.rs"))
        for path in paths:
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
    for cycle in find_cycles(top):
        problems.append(f"import cycle between top-level modules: {' ↔ '.join(cycle)}")
    for folder, graph in siblings.items():
        if not folder:
            continue  # the top level is checked above
        for cycle in find_cycles(graph):
            where = "::".join(folder) or "crate"
            problems.append(f"import cycle among the modules of {where}: {' ↔ '.join(cycle)}")
    for file in sorted((ROOT / "crates").rglob("*.rs")):
        lines = len(file.read_text(encoding="utf-8").splitlines())
        if lines > MAX_LINES:
            problems.append(f"{file.relative_to(ROOT)}: {lines} lines (at most {MAX_LINES})")
    for problem in problems:
        print(problem)
    layers = ", ".join(f"{m} → {{{', '.join(sorted(d))}}}" for m, d in sorted(top.items()))
    print(f"structure: {len(files)} files; imports: {layers}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
