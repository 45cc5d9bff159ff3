#!/usr/bin/env python3
"""Checks that no crate of the workspace has a cycle among its modules (CI runs it).

Every module file is a node: `sim/episode.rs` is `sim::episode`, a folder's `mod.rs` is the
folder's module (`sim`). Each path in non-test code that names a module of the crate is an edge
from the file to the deepest module file the path reaches: `crate::a::b::Item`, `super::x`,
`self::x`, groups such as `crate::{a, b::{c, d}}`, and `child::...` of a child module. A path
through a re-export (`crate::road::Road`, which `road/mod.rs` re-exports from `road/geometry.rs`)
leads to the file that defines the item; `mod child;` and `pub use` themselves are no edges, as they
only name things. So a cycle is code using code that uses it back: a child built on its folder's
`mod.rs` while that `mod.rs` calls the child, or two siblings that import from each other.

Left out as test code: a file's trailing `#[cfg(test)] mod tests { ... }`, and files declared under
`#[cfg(test)]` (`#[cfg(test)] mod stgem_parity;`). Between crates `cargo tree` shows the graph
(Cargo itself refuses cycles there).

    python3 scripts/ci/module_graph.py            # edges and verdict per crate; exit 1 on a cycle
    python3 scripts/ci/module_graph.py --quiet    # only cycles and the verdict
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
IDENT = r"[A-Za-z_][A-Za-z0-9_]*"


def code_of(path):
    """The file's text without comments and without its trailing test module."""
    text = path.read_text()
    cut = text.find("#[cfg(test)]\nmod tests")
    if cut >= 0:
        text = text[:cut]
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return text


def module_of(src, path):
    """`("sim", "episode")` for src/sim/episode.rs, `("sim",)` for src/sim/mod.rs, `()` for the root."""
    parts = list(path.relative_to(src).parts)
    last = parts.pop()[:-3]
    if last != "mod" and not (parts == [] and last in ("lib", "main")):
        parts.append(last)
    return tuple(parts)


def file_of(src, module):
    """The file of a module path, or None when it is no module of the crate."""
    if not module:
        return None
    base = src.joinpath(*module)
    for candidate in (base.with_suffix(".rs"), base / "mod.rs"):
        if candidate.is_file():
            return candidate
    return None


def use_trees(text, start):
    """The paths of a use tree beginning at `start` (just after `crate::`, `super::`, ...)."""
    paths = []

    def tree(i, prefix):
        # Returns the index after this tree.
        while i < len(text) and text[i].isspace():
            i += 1
        if i < len(text) and text[i] == "{":
            i += 1
            while True:
                while i < len(text) and text[i] in " \t\n,":
                    i += 1
                if i >= len(text) or text[i] == "}":
                    return i + 1
                i = tree(i, prefix)
        m = re.compile(IDENT + r"|\*").match(text, i)
        if not m:
            paths.append(prefix)
            return i
        name = m.group(0)
        i = m.end()
        if text.startswith("::", i):
            return tree(i + 2, prefix + [name])
        paths.append(prefix + ([name] if name not in ("*", "self") else []))
        # `as alias`
        alias = re.compile(r"\s+as\s+" + IDENT).match(text, i)
        return alias.end() if alias else i

    tree(start, [])
    return paths


def test_only_children(code):
    """Modules this file declares under `#[cfg(test)]`."""
    return set(re.findall(r"#\[cfg\(test\)\]\s*(?:pub(?:\([^)]*\))?\s+)?mod\s+(" + IDENT + r")\s*;", code))


def use_paths(code, own, parent, children):
    """`(is_reexport, path)` for every module path the code names, relative paths made absolute."""
    found = []
    for m in re.finditer(r"\b(crate|super|self)::", code):
        base = {"crate": (), "super": parent, "self": own}[m.group(1)]
        rest = m.end()
        # `super::super::x`
        while m.group(1) == "super" and code.startswith("super::", rest):
            base = base[:-1]
            rest += len("super::")
        line_start = code.rfind("\n", 0, m.start()) + 1
        reexport = re.match(r"\s*pub(\([^)]*\))?\s+use\b", code[line_start:m.start()]) is not None
        found += [(reexport, base + tuple(p)) for p in use_trees(code, rest)]
    # `use child::...` and `child::item` relative to this module.
    for m in re.finditer(r"(?<![\w:])(pub(?:\([^)]*\))?\s+use\s+|use\s+)?(" + IDENT + r")::", code):
        if m.group(2) in children:
            reexport = m.group(1) is not None and m.group(1).startswith("pub")
            found += [(reexport, own + (m.group(2),) + tuple(p)) for p in use_trees(code, m.end())]
    return found


def edges_of(crate):
    src = crate / "src"
    skipped = set()
    files = sorted(src.rglob("*.rs"))
    for path in files:
        here = module_of(src, path)
        for child in test_only_children(code_of(path)):
            skipped.add(here + (child,))
    modules = {}
    for path in files:
        here = module_of(src, path)
        if any(here[: len(s)] == s for s in skipped):
            continue
        code = code_of(path)
        children = set(re.findall(r"\bmod\s+(" + IDENT + r")\s*;", code))
        modules[here] = use_paths(code, here, here[:-1], children)
    # What each module re-exports: name -> the path it re-exports.
    reexports = {}
    for here, paths in modules.items():
        for is_reexport, path in paths:
            if is_reexport and path:
                reexports.setdefault(here, {})[path[-1]] = path

    def resolve(target, seen=()):
        """The module file that defines what `target` names, following re-exports."""
        for k in range(len(target), 0, -1):
            if file_of(src, target[:k]):
                there, rest = target[:k], target[k:]
                break
        else:
            return None
        if rest and rest[0] in reexports.get(there, {}) and there not in seen:
            deeper = resolve(reexports[there][rest[0]] + rest[1:], seen + (there,))
            if deeper is not None:
                return deeper
        return there

    edges = set()
    for here, paths in modules.items():
        for is_reexport, target in paths:
            # A re-export only names a thing; what uses it depends on where it is defined.
            if is_reexport:
                continue
            there = resolve(target)
            if there is not None and there != here and there not in skipped:
                edges.add(("::".join(here) or "crate", "::".join(there)))
    return edges


def tangles(edges):
    """The groups of modules that reach each other (strongly connected, two or more), sorted."""
    graph = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
        graph.setdefault(b, set())
    index, low, on_stack, stack, groups = {}, {}, set(), [], []

    def visit(node):
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in sorted(graph[node]):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            group = []
            while True:
                top = stack.pop()
                on_stack.discard(top)
                group.append(top)
                if top == node:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    sys.setrecursionlimit(10_000)
    for node in sorted(graph):
        if node not in index:
            visit(node)
    return sorted(groups)


def main():
    quiet = "--quiet" in sys.argv[1:]
    failed = False
    for crate in sorted((ROOT / "crates").iterdir()):
        edges = edges_of(crate)
        print(f"{crate.name}: {len(edges)} edges between modules")
        if not quiet:
            for a, b in sorted(edges):
                print(f"  {a} -> {b}")
        groups = tangles(edges)
        for group in groups:
            failed = True
            print(f"  CYCLE among: {', '.join(group)}")
        if not groups:
            print("  no cycle")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
