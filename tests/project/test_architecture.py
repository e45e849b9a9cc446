"""The house rules of docs/architecture.md: layers import only downward, and no circle, neither between
packages nor between files.

Every ``import drivetrain...`` / ``from drivetrain... import`` in the package (module level, inside a
function or under ``TYPE_CHECKING``: a lazy or a type-only import is still a dependency) is read from the
source with ``ast``. A package's ``__init__`` is a module like any other: ``from drivetrain import
__version__`` is an import of ``drivetrain/__init__.py`` (the public API, which sits on top).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "src" / "drivetrain"

# Lower number = lower layer. A module may import its own layer's siblings and anything below.
LAYERS: dict[str, int] = {
    "errors": 0, "units": 0, "fields": 0, "unit_cache": 0, "jit": 0, "files": 0, "version": 0, "userfile": 0,
    "terminal": 0,
    "physics": 1, "motion": 1, "catalog": 1,
    "axis": 2,
    "duty": 3,
    "sizing": 4,
    "dynamics": 5, "study": 5, "machine": 5,
    "cli": 6, "report": 6, "web": 6,
}
# Faces may use each other only in this direction (the CLI starts the web server and writes reports;
# the web app serves reports).
FACE_EDGES = {("cli", "report"), ("cli", "web"), ("web", "report")}


def _room(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def _module_paths() -> dict[str, Path]:
    """Every module of the package by its dotted name (a package by its ``__init__``: ``drivetrain.catalog``)."""
    out = {}
    for path in PACKAGE.rglob("*.py"):
        rel = path.relative_to(PACKAGE.parent).with_suffix("")
        out[".".join(p for p in rel.parts if p != "__init__")] = path
    return out


def _imports() -> dict[str, set[str]]:
    """Module -> the modules of drivetrain it imports. ``from P import name`` imports the submodule
    ``P.name`` where there is one (``from drivetrain.catalog import db``), else ``P`` itself
    (``from drivetrain import __version__``: ``drivetrain/__init__``)."""
    paths = _module_paths()
    edges: dict[str, set[str]] = {}
    for module, path in paths.items():
        targets: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                targets.update(a.name for a in node.names if a.name.startswith("drivetrain"))
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module \
                    and node.module.split(".")[0] == "drivetrain":
                for a in node.names:
                    sub = f"{node.module}.{a.name}"
                    targets.add(sub if sub in paths else node.module)
        edges[module] = targets - {module}
    return edges


def test_the_reading_sees_package_inits_and_the_version_import() -> None:
    """The import of ``__version__`` from the package's ``__init__`` (the public API, on top of every layer)
    is seen, so a module of a layer that takes it from there is an upward import."""
    paths = _module_paths()
    assert {"drivetrain", "drivetrain.catalog", "drivetrain.cli"} <= set(paths)
    assert "drivetrain.version" in _imports()["drivetrain"]


def test_every_room_has_a_layer() -> None:
    rooms = {_room(m) for m in _imports()} - {"__init__", "__main__"}
    assert rooms <= set(LAYERS), f"add {sorted(rooms - set(LAYERS))} to LAYERS and docs/architecture.md"


def test_layers_import_only_downward() -> None:
    wrong = []
    for module, targets in _imports().items():
        src = _room(module)
        if src in ("__init__", "__main__"):
            continue  # the public API sits on top and may reach every layer
        for target in targets:
            dst = _room(target)
            if dst == "__init__":  # the public API is above every layer
                wrong.append(f"{module} -> {target}")
                continue
            if dst == src:
                continue
            up = LAYERS[dst] > LAYERS[src]
            sideways_face = LAYERS[dst] == LAYERS[src] == LAYERS["cli"] and (src, dst) not in FACE_EDGES
            sideways_engine = LAYERS[dst] == LAYERS[src] and LAYERS[src] in (1, 5) and src != dst
            if up or sideways_face or sideways_engine:
                wrong.append(f"{module} -> {target}")
    assert not wrong, "imports that run the wrong way:\n" + "\n".join(sorted(wrong))


def test_no_circle_between_rooms() -> None:
    graph: dict[str, set[str]] = {}
    for module, targets in _imports().items():
        src = _room(module)
        if src in ("__init__", "__main__"):
            continue
        graph.setdefault(src, set()).update(_room(t) for t in targets if _room(t) not in (src, "__init__"))
    seen: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> None:
        seen[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if seen.get(nxt) == 1:
                pytest.fail("circle: " + " -> ".join([*stack[stack.index(nxt):], nxt]))
            if nxt not in seen:
                visit(nxt)
        stack.pop()
        seen[node] = 2

    for node in sorted(graph):
        if node not in seen:
            visit(node)


def _circle(graph: dict[str, set[str]]) -> list[str] | None:
    """One circle of ``graph`` (its nodes in order, the first repeated at the end), or None."""
    seen: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> list[str] | None:
        seen[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if seen.get(nxt) == 1:
                return [*stack[stack.index(nxt):], nxt]
            if nxt not in seen and (found := visit(nxt)) is not None:
                return found
        stack.pop()
        seen[node] = 2
        return None

    for node in sorted(graph):
        if node not in seen and (found := visit(node)) is not None:
            return found
    return None


def test_no_circle_between_files() -> None:
    """No module imports, directly or through others, a module that imports it (package ``__init__``s
    included): each file can be read, tested and moved after the ones it uses."""
    found = _circle(_imports())
    assert found is None, "circle of files: " + " -> ".join(found or [])


def _third_party_imports(path: Path) -> set[str]:
    """The top-level names of the packages outside drivetrain that a module imports (lazy ones too)."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
    return names - {"drivetrain"}


def test_physics_holds_formulas_not_the_axis_files_models() -> None:
    """``physics/`` holds formulas and the SI types they work on; the axis file's pydantic models (the
    ``drivetrain.fields.Spec`` subclasses, their unions and validators) live in ``axis/``. No module of
    physics, nor any module it reaches through its imports, imports pydantic or ``drivetrain.fields``."""
    paths = _module_paths()
    edges = _imports()
    reached: set[str] = set()
    todo = [m for m in paths if _room(m) == "physics"]
    assert "drivetrain.physics.mechanisms.base" in todo and "drivetrain.physics.transmission" in todo
    while todo:
        module = todo.pop()
        if module not in reached:
            reached.add(module)
            todo.extend(edges[module])
    assert "drivetrain.fields" not in reached, "physics reaches drivetrain.fields (the axis file's field types)"
    wrong = sorted(m for m in reached if "pydantic" in _third_party_imports(paths[m]))
    assert not wrong, f"physics imports pydantic through {wrong}"


def test_a_circle_of_files_is_found() -> None:
    assert _circle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == ["a", "b", "c", "a"]
    assert _circle({"a": {"b"}, "b": set()}) is None


# Modules still waiting for their split along a real seam; this list only shrinks.
PENDING_SPLIT: set[str] = set()


@pytest.mark.parametrize("path", [p for p in sorted(PACKAGE.rglob("*.py"))
                                  if str(p.relative_to(PACKAGE)) not in PENDING_SPLIT],
                         ids=lambda p: str(p.relative_to(PACKAGE)))
def test_module_size(path: Path) -> None:
    """No module over 600 lines without a reason stated in its first lines ("Size:")."""
    text = path.read_text(encoding="utf-8")
    lines = text.count("\n")
    if lines > 600:
        assert "Size:" in "\n".join(text.splitlines()[:40]), f"{path.name}: {lines} lines and no stated reason"
