"""The modules of `src/shoal` import each other in layers, without cycles (issue 29).

The graph is built from the source (`ast`), not by importing: every ``import`` and ``from ... import``
counts, at the top of a module or inside a function (an import deferred to a call is still a dependency;
only ``if TYPE_CHECKING:`` blocks are left out). ``from package import name`` is an edge to the submodule
``package.name`` when that is a module, else to the package's ``__init__``. The implicit import of a
package's ``__init__`` when one of its submodules is imported is not an edge (the root package's
``__init__`` gathers the public API from every layer).

Checked: no cycle; no module imports a name starting with ``_`` from another module; and no module
imports from a layer above its own (`LAYERS`, the order of ``docs/design.md``).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"

LAYERS = [
    # 0: no shoal imports but these
    ["shoal.errors", "shoal.version", "shoal.cache_lock", "shoal.data", "shoal.parallel", "shoal.environment",
     "shoal.cpu_features",
     "shoal.faults"],
    # 1: geometry, physics, neighbour search, backends, integrators; options; file formats
    ["shoal.geometry", "shoal.physics", "shoal.physics.identity", "shoal.physics.shifting", "shoal.neighbours", "shoal.backends",
     "shoal.timestepping", "shoal.options", "shoal.motions", "shoal.mass_properties", "shoal.rigid_body",
     "shoal.body_loads", "shoal.floating", "shoal.body_coupling", "shoal.active_absorption", "shoal.waves",
     "shoal.waves.second_order", "shoal.catenary", "shoal.mooring", "shoal.joints",
     "shoal.relaxation", "shoal.analysis", "shoal.output",
     "shoal.memory",
     "shoal.simulation.resources",
     "shoal.parallel.decomposition", "shoal.parallel.gpu", "shoal.particle_store", "shoal.time_series",
     "shoal.open_boundary", "shoal.particle_buffers"],
    # 2: cases as data
    ["shoal.probes", "shoal.case", "shoal.casefile", "shoal.cases", "shoal.advice"],
    # 3: the model of particles and scheme
    ["shoal.model", "shoal.parallel.collective", "shoal.parallel.halo", "shoal.parallel.timed_comm",
     "shoal.parallel.migration", "shoal.parallel.rebalancer"],
    ["shoal.parallel.model", "shoal.build"],
    # 5: the time loop, its callbacks and checkpoints
    ["shoal.simulation", "shoal.parallel.checkpoint"],
    # 6: running a case end to end, the command line, post-processing, validation
    ["shoal.runner", "shoal.parallel.run", "shoal.check", "shoal.post", "shoal.probes.offline", "shoal.output.isosurface",
     "shoal.output.plot_case", "shoal.validation", "shoal.cli", "shoal.__main__", "shoal"],
]


def modules():
    """{dotted name: path} of every module under src/shoal."""
    out = {}
    for p in (SRC / "shoal").rglob("*.py"):
        parts = p.relative_to(SRC).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


def _targets(name, path, node, mods):
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    if isinstance(node, ast.Import):
        return [a.name for a in node.names]
    if node.level:
        base = package.split(".")
        base = base[:len(base) - (node.level - 1)]
        mod = ".".join(base + ([node.module] if node.module else []))
    else:
        mod = node.module
    return [f"{mod}.{a.name}" if f"{mod}.{a.name}" in mods else mod for a in node.names]


def import_graph():
    """({module: set of shoal modules it imports}, [(module, from, private name)])."""
    mods = modules()
    edges, private = {m: set() for m in mods}, []
    for name, path in mods.items():
        def walk(node):
            for child in ast.iter_child_nodes(node):
                if isinstance(child, ast.If) and "TYPE_CHECKING" in ast.unparse(child.test):
                    continue
                if isinstance(child, (ast.Import, ast.ImportFrom)):
                    for t in _targets(name, path, child, mods):
                        while t not in mods and "." in t:
                            t = t.rsplit(".", 1)[0]
                        if t in mods and t != name:
                            edges[name].add(t)
                    if isinstance(child, ast.ImportFrom) and (child.level or (child.module or "").startswith("shoal")):
                        private.extend((name, child.module or ".", a.name) for a in child.names
                                       if a.name.startswith("_") and not a.name.startswith("__"))
                walk(child)

        walk(ast.parse(path.read_text(), str(path)))
    return edges, private


def cycles(edges):
    """The strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, found, counter = {}, {}, [], set(), [], [0]

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
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return found


def layer(module):
    """The layer of `module`: that of the longest prefix listed in `LAYERS`."""
    best = (None, -1)
    for k, names in enumerate(LAYERS):
        for p in names:
            if (module == p or module.startswith(p + ".")) and len(p) > best[1]:
                best = (k, len(p))
    return best[0]


@pytest.fixture(scope="module")
def graph():
    return import_graph()


def test_the_graph_sees_deferred_imports(graph):
    """The builder finds an import inside a function (Simulation builds a Model from a Case there)."""
    edges, _ = graph
    assert "shoal.build" in edges["shoal.simulation.simulation"]
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_no_import_cycle(graph):
    edges, _ = graph
    found = cycles(edges)
    detail = "; ".join(" <-> ".join(c) + ": " + ", ".join(f"{m} -> {t}" for m in c for t in sorted(edges[m]) if t in c)
                       for c in found)
    assert not found, f"import cycles: {detail}"


def test_no_private_name_imported_from_another_module(graph):
    _, private = graph
    assert not private, "private names imported: " + ", ".join(f"{m} imports {n} from {f}" for m, f, n in private)


def test_every_module_is_in_a_layer_and_imports_only_its_own_or_lower(graph):
    edges, _ = graph
    assert not [m for m in edges if layer(m) is None], "modules in no layer"
    upward = [f"{m} (layer {layer(m)}) imports {t} (layer {layer(t)})" for m in sorted(edges) for t in sorted(edges[m])
              if layer(t) > layer(m)]
    assert not upward, "; ".join(upward)
