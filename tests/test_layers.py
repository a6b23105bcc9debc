"""The package's import graph, read from its sources with ``ast``: no import circle, and the
layer rule of ``attentive_gym/__init__.py`` (the attention library stands alone).

Every import statement counts, at module level or inside a function: a lazy import inside a
function runs as soon as the function does, and one that goes up a layer is how a circle
hides (the module level stays acyclic while the program is not). Only imports under
``if TYPE_CHECKING:`` are left out, since they never run.

The attention library's rule is an allow-list, so that a new subpackage or dependency is
refused until it is allowed here on purpose.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

import attentive_gym

PACKAGE = "attentive_gym"
ROOT = Path(attentive_gym.__file__).parent
ATTENTION = f"{PACKAGE}.attention"
#: Third-party packages the attention library may import anywhere (``attentive_gym/__init__.py``:
#: pure numpy, compiled with numba, whose llvmlite it reaches for its intrinsics). Besides these: the
#: standard library, its own modules and the package's top-level private modules (``attentive_gym._*``).
ATTENTION_ALLOWS_EXTERNAL = frozenset({"numpy", "numba", "llvmlite"})
#: Third-party packages it may import only inside a function, so that importing the library never
#: needs them: rosbags, the ``ros`` extra (``attention.io.rosbag`` reads ROS bags with it).
ATTENTION_ALLOWS_LAZY = frozenset({"rosbags"})


def module_name(path: Path) -> str:
    """``attentive_gym/agents/training.py`` → ``attentive_gym.agents.training``; a package's
    ``__init__.py`` → the package."""
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def package_modules() -> dict[str, Path]:
    """Every module of the package, by dotted name."""
    return {module_name(path): path for path in sorted(ROOT.rglob("*.py"))}


def _is_type_checking_block(node: ast.AST) -> bool:
    return isinstance(node, ast.If) and ast.unparse(node.test) in ("TYPE_CHECKING", "typing.TYPE_CHECKING")


def _import_nodes(tree: ast.AST, *, into_functions: bool = True):
    """The ``Import`` and ``ImportFrom`` nodes of ``tree`` at any depth, but not under ``if TYPE_CHECKING:``;
    with ``into_functions=False`` only those that run on import (none inside a function's body)."""
    stack = [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
        elif _is_type_checking_block(node):
            stack.extend(node.orelse)
        elif into_functions or not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            stack.extend(ast.iter_child_nodes(node))


def imported_names(name: str, path: Path, *, module_level_only: bool = False) -> set[str]:
    """The dotted names module ``name`` (at ``path``) imports: ``import a.b`` → ``a.b``;
    ``from a import b`` → ``a.b`` (``b`` may be a submodule or an attribute of ``a``: ``_resolve``
    tells); ``from a import *`` → ``a``; relative imports resolved against the module's package.
    With ``module_level_only``, only the imports that run when the module is imported (not those
    inside functions)."""
    is_package = path.name == "__init__.py"
    names = set()
    tree = ast.parse(path.read_text(), filename=str(path))
    for node in _import_nodes(tree, into_functions=not module_level_only):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
            continue
        base = node.module or ""
        if node.level:
            package = name.split(".") if is_package else name.split(".")[:-1]
            anchor = package[: len(package) - (node.level - 1)]
            base = ".".join([*anchor, base] if base else anchor)
        names.update(base if alias.name == "*" else f"{base}.{alias.name}" for alias in node.names)
    return names


def _resolve(imported: str, modules: dict[str, Path]) -> str | None:
    """The package module that importing ``imported`` loads itself (its longest prefix that is one), or None."""
    parts = imported.split(".")
    for end in range(len(parts), 0, -1):
        candidate = ".".join(parts[:end])
        if candidate in modules:
            return candidate
    return None


def import_graph(modules: dict[str, Path]) -> dict[str, set[str]]:
    """Module → the package modules it imports (itself left out: ``from pkg import name`` inside
    ``pkg/__init__.py`` reads its own attribute)."""
    graph = {}
    for name, path in modules.items():
        targets = {_resolve(imported, modules) for imported in imported_names(name, path)}
        graph[name] = {target for target in targets if target is not None and target != name}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One cycle (``[a, b, ..., a]``) through each strongly connected component of more than one
    module (Tarjan's algorithm, then a shortest way back to the component's first module)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    components: list[list[str]] = []

    def visit(node: str) -> None:
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
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                components.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return [_cycle_through(component, graph) for component in components]


def _cycle_through(component: list[str], graph: dict[str, set[str]]) -> list[str]:
    """A shortest path from ``component[0]`` back to itself inside ``component`` (breadth first)."""
    start, members = component[0], set(component)
    previous: dict[str, str] = {}
    frontier = [start]
    while frontier:
        following = []
        for node in frontier:
            for nxt in sorted(graph[node] & members):
                if nxt == start:
                    path = [node]
                    while path[-1] != start:
                        path.append(previous[path[-1]])
                    return [start, *reversed(path[:-1]), start]
                if nxt not in previous:
                    previous[nxt] = node
                    following.append(nxt)
        frontier = following
    raise AssertionError(f"{component} is not strongly connected")


def test_the_graph_finder_sees_lazy_and_relative_imports(tmp_path):
    """The reader itself: a function-level import counts, a TYPE_CHECKING one does not, relative ones
    resolve, ``from module import name`` is an edge to the module, and the lazy circle is found."""
    package = tmp_path / PACKAGE / "agents"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("from .a import thing\n")
    source = package / "a.py"
    source.write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from attentive_gym.world import World\n"
        "def f():\n    from . import b\n    import attentive_gym.attention.model as m\n"
    )
    assert imported_names(f"{PACKAGE}.agents.a", source) == {
        "typing.TYPE_CHECKING",
        f"{PACKAGE}.agents.b",
        f"{PACKAGE}.attention.model",
    }
    assert imported_names(f"{PACKAGE}.agents.a", source, module_level_only=True) == {"typing.TYPE_CHECKING"}
    assert imported_names(f"{PACKAGE}.agents", package / "__init__.py") == {f"{PACKAGE}.agents.a.thing"}
    (package / "b.py").write_text("from attentive_gym.agents.a import f\n")
    modules = {
        f"{PACKAGE}.agents": package / "__init__.py",
        f"{PACKAGE}.agents.a": source,
        f"{PACKAGE}.agents.b": package / "b.py",
    }
    graph = import_graph(modules)
    assert graph == {
        f"{PACKAGE}.agents": {f"{PACKAGE}.agents.a"},
        f"{PACKAGE}.agents.a": {f"{PACKAGE}.agents.b"},
        f"{PACKAGE}.agents.b": {f"{PACKAGE}.agents.a"},
    }
    assert cycles(graph) == [[f"{PACKAGE}.agents.a", f"{PACKAGE}.agents.b", f"{PACKAGE}.agents.a"]]


def test_cycles_names_each_circle_and_nothing_else():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": set(), "e": {"f"}, "f": {"e"}, "g": {"a"}}
    assert cycles(graph) == [["a", "b", "c", "a"], ["e", "f", "e"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_the_graph_covers_the_package():
    modules = package_modules()
    assert {f"{PACKAGE}.agents.training", f"{PACKAGE}.agents.backends", f"{PACKAGE}.attention"} <= set(modules)
    graph = import_graph(modules)
    assert f"{PACKAGE}.agents.training" in graph[f"{PACKAGE}.agents.backends"]  # run_job's lazy import is seen


def test_no_import_circle():
    found = cycles(import_graph(package_modules()))
    assert not found, "import circles (each module imports the next):\n" + "\n".join(" -> ".join(c) for c in found)


def attention_import_refusals(name: str, path: Path, modules: dict[str, Path]) -> list[str]:
    """The imports of attention-library module ``name`` (at ``path``) that its allow-list refuses,
    each with the reason; ``modules``: the package's modules, by dotted name."""
    module_level = imported_names(name, path, module_level_only=True)
    refused = []
    for imported in sorted(imported_names(name, path)):
        top = imported.split(".")[0]
        if top == PACKAGE:
            if imported == ATTENTION or imported.startswith(ATTENTION + "."):
                continue
            loaded = _resolve(imported, modules)
            if loaded is not None and loaded.count(".") == 1 and loaded.split(".")[1].startswith("_"):
                continue
            refused.append(f"{imported} (a part of {PACKAGE} outside the attention library and its private helpers)")
        elif top in sys.stdlib_module_names or top in ATTENTION_ALLOWS_EXTERNAL:
            continue
        elif top in ATTENTION_ALLOWS_LAZY:
            if imported in module_level:
                refused.append(f"{imported} (at module level; {top} may be imported only inside a function)")
        else:
            refused.append(f"{imported} (a third-party package not on the allow-list)")
    return refused


def test_the_attention_rule_refuses_what_is_not_allowed(tmp_path):
    """The allow-list itself: a layer above, a sibling subpackage, a public top-level module, an
    unlisted third-party package and a module-level rosbags import are refused; what is allowed passes."""
    modules = package_modules()
    source = tmp_path / "probe.py"
    source.write_text(
        "import os.path\nimport numpy as np\nfrom numba import njit\nfrom attentive_gym._atomic import atomic_file\n"
        "from . import config\nimport rosbags.typesys\nimport matplotlib.pyplot\n"
        "from attentive_gym.perception import geometry\nfrom attentive_gym import registration\n"
        "def read():\n    from rosbags.highlevel import AnyReader\n    import yaml\n"
        "    from attentive_gym.viz import x\n"
    )
    refused = attention_import_refusals(f"{ATTENTION}.probe", source, modules)
    assert [entry.split(" ")[0] for entry in refused] == [
        f"{PACKAGE}.perception.geometry",
        f"{PACKAGE}.registration",
        f"{PACKAGE}.viz.x",
        "matplotlib.pyplot",
        "rosbags.typesys",
        "yaml",
    ]


@pytest.mark.parametrize(
    "name", sorted(n for n in package_modules() if n == ATTENTION or n.startswith(ATTENTION + "."))
)
def test_the_attention_library_imports_only_what_it_may(name):
    """``attentive_gym.attention`` is pure numpy (+ numba): no simulator, no RL stack, no plotting,
    nothing above it (the allow-list of ``attention_import_refusals``)."""
    modules = package_modules()
    refused = attention_import_refusals(name, modules[name], modules)
    assert not refused, (
        f"{name} imports " + "; ".join(refused) + f": the attention library may import the standard library, "
        f"{', '.join(sorted(ATTENTION_ALLOWS_EXTERNAL))}, {', '.join(sorted(ATTENTION_ALLOWS_LAZY))} inside "
        f"functions only, its own modules and {PACKAGE}'s top-level private modules ({PACKAGE}._*)"
    )


#: The package's layers from the bottom up (``attentive_gym/__init__.py``): a module may import
#: its own subpackage and the layers below its own, never one beside or above it. The command
#: line (``cli``) is the top; the other top-level modules (``registration``, ``progress``, the
#: private ``_*`` helpers) stand outside the layers.
LAYERS: tuple[frozenset[str], ...] = (
    frozenset({"attention"}),
    frozenset({"sensors"}),
    frozenset({"world"}),
    frozenset({"envs"}),
    frozenset({"wrappers"}),
    frozenset({"vector"}),
    frozenset({"perception", "viz"}),
    frozenset({"agents", "experiments"}),
    frozenset({"cli"}),
)
RANK = {package: rank for rank, layer in enumerate(LAYERS) for package in layer}


def layer_refusals(name: str, targets: set[str]) -> list[str]:
    """The package modules among ``targets`` that module ``name`` may not import by ``LAYERS``."""
    own = name.split(".")[1] if name.count(".") >= 1 else None
    if own not in RANK:
        return []
    refused = []
    for target in sorted(targets):
        other = target.split(".")[1] if target.count(".") >= 1 else None
        if other is None or other == own or other not in RANK:
            continue
        if RANK[other] >= RANK[own]:
            refused.append(f"{target} ({other} is {'beside' if RANK[other] == RANK[own] else 'above'} {own})")
    return refused


def test_the_layer_rule_refuses_imports_beside_and_above():
    assert layer_refusals(f"{PACKAGE}.envs.x", {f"{PACKAGE}.wrappers.variants", f"{PACKAGE}.world.world"}) == [
        f"{PACKAGE}.wrappers.variants (wrappers is above envs)"
    ]
    assert layer_refusals(f"{PACKAGE}.agents.x", {f"{PACKAGE}.experiments.y", f"{PACKAGE}.vector.sb3"}) == [
        f"{PACKAGE}.experiments.y (experiments is beside agents)"
    ]
    assert layer_refusals(f"{PACKAGE}.vector.fleet", {f"{PACKAGE}.registration", f"{PACKAGE}.vector.protocol"}) == []


def test_every_subpackage_has_its_layer():
    """Every subpackage is placed; every placed name is a subpackage or a top-level module (``cli``)."""
    names = {name.split(".")[1] for name in package_modules() if name.count(".") >= 1}
    packages = {name for name in names if (ROOT / name).is_dir()}
    assert packages <= set(RANK), f"subpackages placed in no layer: {sorted(packages - set(RANK))}"
    assert set(RANK) <= names, f"placed but gone: {sorted(set(RANK) - names)}"


def test_no_import_runs_against_the_layers():
    graph = import_graph(package_modules())
    refused = {name: layer_refusals(name, targets) for name, targets in graph.items()}
    refused = {name: found for name, found in refused.items() if found}
    assert not refused, (
        "imports against the layers (bottom up: "
        + " < ".join("/".join(sorted(layer)) for layer in LAYERS)
        + "):\n"
        + "\n".join(f"{name} imports {', '.join(found)}" for name, found in refused.items())
    )
