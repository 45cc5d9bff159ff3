#!/usr/bin/env python3
"""Checks that no crate of the workspace has a cycle among its modules.

For each crate under crates/, every `crate::a::b` path in non-test code (comments and the
`#[cfg(test)]` module at the end of a file left out) is an edge from the file's top-level module to
`a`. The script prints each crate's edges between top-level modules (a folder such as `sim/`, or
a file such as `records.rs`) and fails if they form a cycle. Between crates, `cargo tree` shows the
graph (Cargo itself refuses cycles there).

    python3 scripts/module_graph.py
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def code_of(path):
    """The file's text without comments and without its trailing test module."""
    text = path.read_text()
    cut = text.find("#[cfg(test)]\nmod tests")
    if cut >= 0:
        text = text[:cut]
    text = re.sub(r"//[^\n]*", "", text)
    return text


def top_module(src, path):
    """`sim` for src/sim/episode.rs, `records` for src/records.rs, None for the crate root."""
    rel = path.relative_to(src).parts
    if len(rel) == 1:
        name = rel[0][:-3]
        return None if name in ("lib", "main") else name
    return rel[0]


def edges_of(crate):
    src = crate / "src"
    edges = set()
    for path in sorted(src.rglob("*.rs")):
        here = top_module(src, path)
        if here is None:
            continue
        code = code_of(path)
        names = [m.group(1) for m in re.finditer(r"\bcrate::(\w+)", code)]
        # `use crate::{a, b::c}` groups.
        for group in re.finditer(r"\bcrate::\{([^}]*)\}", code):
            names += [item.split("::")[0].strip() for item in group.group(1).split(",")]
        for there in names:
            is_module = (src / f"{there}.rs").exists() or (src / there).is_dir()
            if is_module and there != here:
                edges.add((here, there))
    return edges


def cycle(edges):
    """A cycle of the directed graph, or None."""
    graph = {}
    for a, b in edges:
        graph.setdefault(a, []).append(b)
    state = {}
    stack = []

    def visit(node):
        state[node] = "open"
        stack.append(node)
        for nxt in graph.get(node, []):
            if state.get(nxt) == "open":
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        state[node] = "done"
        stack.pop()
        return None

    for node in sorted(graph):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


def main():
    failed = False
    for crate in sorted((ROOT / "crates").iterdir()):
        edges = edges_of(crate)
        print(f"{crate.name}:")
        for a, b in sorted(edges):
            print(f"  {a} -> {b}")
        found = cycle(edges)
        if found:
            failed = True
            print(f"  CYCLE: {' -> '.join(found)}")
        else:
            print("  no cycle")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
