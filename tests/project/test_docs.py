"""The axis-file reference (docs/axis-file.md): every example validates, every type has a section.

Each ```yaml block that holds ``mechanism:`` is parsed with the same loader and model as the CLI
(``parse_yaml`` + ``parse_axis``), its profile is built into a cycle and its duty cycle computed,
so a documented example cannot drift from what the code accepts.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from drivetrain.axis.mechanisms import MECHANISM_TYPES
from drivetrain.axis.model import parse_axis
from drivetrain.axis.transmission import TRANSMISSION_TYPES
from drivetrain.axis.yaml_text import parse_yaml
from drivetrain.duty.cycle import duty_cycle

DOCS = Path(__file__).parents[2] / "docs"
AXIS_FILE = DOCS / "axis-file.md"
FENCE = re.compile(r"^```yaml[ \t]*\n(.*?)^```[ \t]*$", re.MULTILINE | re.DOTALL)


def _text() -> str:
    return AXIS_FILE.read_text(encoding="utf-8")


def _examples() -> list[tuple[int, str]]:
    """(line number, YAML text) of every yaml block that describes an axis."""
    text = _text()
    return [(text.count("\n", 0, m.start()) + 2, m.group(1)) for m in FENCE.finditer(text)
            if re.search(r"^mechanism:", m.group(1), re.MULTILINE)]


def _sections() -> dict[str, set[str]]:
    """Backticked names in the ### headings under each ## heading."""
    out: dict[str, set[str]] = {}
    h2 = ""
    in_fence = False
    for line in _text().splitlines():
        if line.startswith("```"):
            in_fence = not in_fence
        if in_fence:
            continue
        if line.startswith("## "):
            h2 = line[3:].strip().lower()
            out.setdefault(h2, set())
        elif line.startswith("### "):
            out.setdefault(h2, set()).update(re.findall(r"`([a-z_]+)`", line))
    return out


EXAMPLES = _examples()


def test_there_are_examples() -> None:
    assert len(EXAMPLES) >= len(MECHANISM_TYPES) + len(TRANSMISSION_TYPES)


@pytest.mark.parametrize(("line", "source"), EXAMPLES, ids=[f"line{n}" for n, _ in EXAMPLES])
def test_example_validates(line: int, source: str) -> None:
    axis = parse_axis(parse_yaml(source, f"{AXIS_FILE.name}:{line}"))
    if axis.spec.profile:
        duty = duty_cycle(axis, points_per_phase=9)
        assert duty.period > 0.0


def test_every_mechanism_type_has_a_section_and_an_example() -> None:
    sections = _sections()
    assert set(MECHANISM_TYPES) <= sections.get("mechanisms", set())
    used = {parse_yaml(src)["mechanism"]["type"] for _, src in EXAMPLES}
    assert set(MECHANISM_TYPES) <= used


def test_every_transmission_type_has_a_section_and_an_example() -> None:
    sections = _sections()
    assert set(TRANSMISSION_TYPES) <= sections.get("transmission elements", set())
    used = {t["type"] for _, src in EXAMPLES for t in parse_yaml(src).get("transmission") or []}
    assert set(TRANSMISSION_TYPES) <= used


def test_the_load_test_paces_clients_like_the_page() -> None:
    """make bench's 'page pace' think time is the page's own re-size delay (static/app.js)."""
    root = Path(__file__).resolve().parents[2]
    js = (root / "src" / "drivetrain" / "web" / "static" / "app.js").read_text(encoding="utf-8")
    m = re.search(r"const SIZE_DELAY_MS = (\d+);", js)
    assert m is not None
    run_all = (root / "bench" / "run_all.py").read_text(encoding="utf-8")
    assert f'"--think", "{m.group(1)}"' in run_all
