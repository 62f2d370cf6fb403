"""The Python harness in layers: every import between esph's modules, at
module level or inside a function, goes down (or sideways within a layer)
and none closes a cycle.

    0  theory, paths, report, plots        no esph imports but their own layer's
    1  problems (the catalogue), schemes   what is solved and by which scheme
    2  fe (solver, meshes, tables), runner the FE reference, running LAMMPS
    3  validate, speed, matrix, ...        the commands' work
    4  cli, __main__, fe.__main__          argument parsers only

A module not listed here (a new one) is checked for cycles only."""
from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "esph"

LAYERS = (
    ("theory", "paths", "report", "plots"),
    ("problems", "schemes"),
    ("fe", "fe.meshes", "fe.solver", "fe.tables", "runner"),
    ("reference", "beam", "validate", "speed", "matrix", "statics", "bench3d", "rings",
     "figures", "spheres3d", "weak", "bench"),
    ("cli", "__main__", "fe.__main__", "results_page"),
)
RANK = {name: k for k, names in enumerate(LAYERS) for name in names}


def module_name(path: Path) -> str:
    """esph-relative dotted name: fe.solver, fe (for fe/__init__.py), cli."""
    parts = list(path.relative_to(PACKAGE).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> dict[str, Path]:
    found = {module_name(p): p for p in PACKAGE.rglob("*.py")}
    found.pop("", None)         # esph/__init__.py
    return found


def resolve(name: str, known) -> str | None:
    """The esph module a dotted esph-relative name denotes: itself if it is a
    module, else the package (or module) that defines it; None outside esph."""
    while name:
        if name in known:
            return name
        name = name.rpartition(".")[0]
    return None


def imports(name: str, path: Path, known) -> set[str]:
    """The esph modules `name` imports anywhere in its source (functions too)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            targets = [a.name[len("esph."):] for a in node.names if a.name.startswith("esph.")]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".") if package else []
                base = base[:len(base) - (node.level - 1)] if node.level > 1 else base
                base = ".".join(base + ([node.module] if node.module else []))
            elif node.module == "esph" or (node.module or "").startswith("esph."):
                base = node.module[len("esph"):].lstrip(".")
            else:
                continue
            # `from . import fe` names a module; `from .fe import tip` a name in it
            targets = [".".join(filter(None, (base, a.name))) for a in node.names]
            targets = [t if t in known else base for t in targets]
        else:
            continue
        for t in targets:
            found = resolve(t, known)
            if found and found != name:
                out.add(found)
    return out


def graph() -> dict[str, set[str]]:
    known = modules()
    return {name: imports(name, path, known) for name, path in known.items()}


def cycles(g: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(g.get(v, ())):
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
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(g):
        if v not in index:
            visit(v)
    return out


def test_the_import_graph_is_read():
    g = graph()
    assert "problems" in g["validate"] and "runner" in g["validate"]
    assert "theory" in g["problems"]


def test_no_import_cycle():
    assert cycles(graph()) == []


def test_imports_go_down_the_layers():
    upward = [f"{a} (layer {RANK[a]}) imports {b} (layer {RANK[b]})"
              for a, targets in sorted(graph().items()) if a in RANK
              for b in sorted(targets) if b in RANK and RANK[b] > RANK[a]]
    assert upward == []


def test_theory_stands_alone():
    assert graph()["theory"] == set()


def test_no_argument_parser_below_the_commands():
    """argparse only in the entry points (layer 4)."""
    parsers = [name for name, path in modules().items()
               if RANK.get(name, len(LAYERS) - 1) < len(LAYERS) - 1 and "argparse" in
               {a.name for n in ast.walk(ast.parse(path.read_text())) if isinstance(n, ast.Import)
                for a in n.names}]
    assert parsers == []
