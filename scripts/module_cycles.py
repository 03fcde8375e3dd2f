#!/usr/bin/env python3
"""Import cycles among a crate's modules, and imports against the crate's layer order.

Reads every `.rs` file under a crate's `src/`, takes the `crate::…` and `super::…` paths its
code names (comments and doc comments left out), resolves each to the deepest module file it
reaches, and prints the strongly connected components of that graph with more than one
module. With `--layers a,b,c` (the crate's top-level modules, lowest layer first, as
`docs/architecture.md` lists them) it also prints every import of a higher layer by a lower
one, and every top-level module the list leaves out. Exits 1 if there is any cycle or upward
import: data must flow one way through the library's layers.

    python3 scripts/module_cycles.py crates/pvfc-sim/src [--graph] [--layers plant,contact,…]
"""

import pathlib
import re
import sys


def module_of(src: pathlib.Path, f: pathlib.Path) -> tuple:
    parts = list(f.relative_to(src).with_suffix("").parts)
    if parts[-1] in ("mod", "lib", "main"):
        parts = parts[:-1]
    return tuple(parts)


def code_of(text: str) -> str:
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return "\n".join(line.split("//")[0] for line in text.splitlines())


def main() -> int:
    src = pathlib.Path(sys.argv[1])
    files = {module_of(src, f): f for f in sorted(src.rglob("*.rs"))}
    mods = set(files)
    edges = {m: set() for m in mods}
    path = re.compile(r"\b(crate|super)((?:::[A-Za-z_][A-Za-z_0-9]*)+)")
    group = re.compile(r"\b(crate|super)((?:::[A-Za-z_][A-Za-z_0-9]*)*)::\{([^}]*)\}")
    for m, f in files.items():
        code = code_of(f.read_text(encoding="utf-8"))
        refs = [(k, p) for k, p in path.findall(code)]
        for k, p, inner in group.findall(code):
            for item in inner.split(","):
                item = item.strip().split(" as ")[0].split("::")[0].strip()
                if item and item != "self":
                    refs.append((k, p + "::" + item))
        for kind, p in refs:
            names = [x for x in p.split("::") if x]
            # `super` is the parent of the module the file defines.
            target = () if kind == "crate" else m[:-1]
            for n in names:
                if target + (n,) in mods:
                    target = target + (n,)
                else:
                    break
            # The crate root (lib.rs: macros, re-exports) is not a layer.
            if target not in ((), m):
                edges[m].add(target)
    # Tarjan's strongly connected components.
    index, low, stack, on, sccs = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            sccs.append(comp)

    sys.setrecursionlimit(10000)
    for v in sorted(mods):
        if v not in index:
            visit(v)
    name = lambda t: "::".join(t) or "crate"
    if "--graph" in sys.argv:
        for m in sorted(mods):
            print(f"{name(m)} -> {', '.join(sorted(name(t) for t in edges[m]))}")
    cycles = [sorted(c) for c in sccs if len(c) > 1]
    print(f"{len(mods)} modules, {sum(len(e) for e in edges.values())} imports, {len(cycles)} cycles")
    for c in cycles:
        print("cycle: " + " ↔ ".join(name(t) for t in c))
    upward = layer_violations(mods, edges, name)
    return 1 if cycles or upward else 0


def layer_violations(mods, edges, name) -> int:
    """Prints the imports against `--layers` (and the top-level modules it leaves out);
    gives their number (0 without `--layers`)."""
    if "--layers" not in sys.argv:
        return 0
    order = sys.argv[sys.argv.index("--layers") + 1].split(",")
    rank = {layer: i for i, layer in enumerate(order)}
    bad = 0
    for top in sorted({m[0] for m in mods if m} - set(rank)):
        print(f"layers: the top-level module {top} is in no layer of --layers")
        bad += 1
    for m in sorted(mods):
        for t in sorted(edges[m]):
            if m and t and m[0] != t[0] and rank.get(t[0], -1) > rank.get(m[0], -1):
                print(f"upward import: {name(m)} (layer {m[0]}) imports {name(t)} (layer {t[0]}, higher)")
                bad += 1
    print(f"layers {' < '.join(order)}: {bad} violations")
    return bad


if __name__ == "__main__":
    sys.exit(main())
