"""The house rules of docs/architecture.md: layers import only downward, and no circle.

Every ``import drivetrain...`` / ``from drivetrain... import`` in the package (module level or inside a
function: a lazy import is still a dependency) is read from the source with ``ast``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "drivetrain"

# Lower number = lower layer. A module may import its own layer's siblings and anything below.
LAYERS: dict[str, int] = {
    "errors": 0, "units": 0, "fields": 0, "unit_cache": 0, "jit": 0, "userfile": 0,
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


def _imports() -> dict[str, set[str]]:
    edges: dict[str, set[str]] = {}
    for path in PACKAGE.rglob("*.py"):
        rel = path.relative_to(PACKAGE.parent).with_suffix("")
        module = ".".join(p for p in rel.parts if p != "__init__")
        targets: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                targets.update(a.name for a in node.names if a.name.startswith("drivetrain"))
            elif isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("drivetrain"):
                if node.module == "drivetrain":  # from drivetrain import catalog, __version__
                    targets.update(f"drivetrain.{a.name}" for a in node.names if a.name in LAYERS)
                else:
                    targets.add(node.module)
        edges[module] = targets
    return edges


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
            if dst in ("__init__", src):
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
