"""The typed blocks of the answer (``sizing.electrical.DriveAnswer``, ``Regen``, ``RegenEvent``): every field
documented with its unit, the JSON they make the one docs/axis-file.md documents, and the ``--json`` of the
shipped examples unchanged by their being typed."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest

from drivetrain import cli
from drivetrain.sizing.electrical import _DRIVE_KEYS, DriveAnswer, Regen, RegenEvent

ROOT = Path(__file__).resolve().parents[2]
JSON_DATA = ROOT / "tests" / "data" / "json"
TYPED = (DriveAnswer, Regen, RegenEvent)
VOLATILE = re.compile(r'^  "(drivetrain_version|catalog_version)": .*\n', re.MULTILINE)


def attributes(cls: type) -> list[tuple[str, str, str]]:
    """(name, type, description) of each entry of the numpy-style ``Attributes`` section of ``cls``'s docstring."""
    doc = cls.__doc__ or ""
    section = doc.split("Attributes\n    ----------\n", 1)
    assert len(section) == 2, f"{cls.__name__} has no Attributes section"
    out: list[tuple[str, str, str]] = []
    for line in section[1].splitlines():
        head = re.match(r"^    (\w+) : (.+)$", line)
        if head:
            out.append((head.group(1), head.group(2), ""))
        elif line.startswith("        ") and out:
            name, typ, text = out[-1]
            out[-1] = (name, typ, (text + " " + line.strip()).strip())
        elif line.strip() and not line.startswith("    "):
            break
    return out


def assert_documented(cls: type) -> None:
    """Every field of the dataclass ``cls`` is described in its ``Attributes`` section, in order, a float
    with its unit in brackets."""
    documented = attributes(cls)
    assert [d[0] for d in documented] == [f.name for f in dataclasses.fields(cls)]
    for name, typ, text in documented:
        assert text, f"{cls.__name__}.{name} has no description"
        if typ.startswith("float"):  # a quantity states its unit
            assert re.search(r"\[[^\]]+\]", text), f"{cls.__name__}.{name}: no unit in {text!r}"


@pytest.mark.parametrize("cls", TYPED, ids=lambda c: c.__name__)
def test_every_field_is_documented_in_order_with_its_unit(cls: type) -> None:
    assert_documented(cls)


def test_the_regen_keys_are_the_documented_ones() -> None:
    """docs/axis-file.md, "Top-level `regen` block": the table's keys are Regen.to_dict()'s, in order."""
    text = (ROOT / "docs" / "axis-file.md").read_text(encoding="utf-8")
    table = text.split("Top-level `regen` block:", 1)[1].split("\n\n", 2)[1]
    keys = [k for row in table.splitlines()[2:] for k in re.findall(r"`(\w+)`", row.split("|")[1])]
    regen = Regen(1.0, 0.1, 0.9, 0.2, "published", 0.2, 0.7, 30.0, 2.0, 40.0, 600.0, True, None,
                  (RegenEvent(0.1, 0.2, 0.9, 0.7),))
    assert list(regen.to_dict()) == keys
    assert list(regen.to_dict()["events"][0]) == ["t0_s", "t1_s", "energy_J", "resistor_J"]
    assert "events" not in regen.to_dict(events=False)


def test_every_drive_key_is_a_field_and_documented() -> None:
    """Each layout's JSON keys are fields of DriveAnswer and named in docs/axis-file.md's drive sections."""
    text = (ROOT / "docs" / "axis-file.md").read_text(encoding="utf-8")
    docs = text.split("Top-level `drive` block:", 1)[1].split("Top-level `regen` block:", 1)[0]
    docs += text.split("### Drives in a selection", 1)[1].split("The selected motor is the best-ranked", 1)[0]
    documented = set(re.findall(r"`(\w+)`", docs))
    names = {f.name for f in dataclasses.fields(DriveAnswer)}
    for layout, keys in _DRIVE_KEYS.items():
        assert set(keys) <= names, layout
        missing = set(keys) - documented
        assert not missing, (layout, missing)


def test_a_drive_block_leaves_out_what_is_not_known_and_keeps_its_order() -> None:
    given = DriveAnswer("given motor", id="D1", vendor=None, continuous_current_A=2.0, peak_current_A=6.0, ok=True,
                        checks=())
    assert given.to_dict() == {"id": "D1", "vendor": None, "continuous_current_A": 2.0, "peak_current_A": 6.0,
                               "ok": True, "checks": []}
    assert given.outcome == "ok" and given.status is None
    none = DriveAnswer("not checked", basis="vendor and supply voltage", candidates=(), status="none", reason="no")
    assert list(none.to_dict()) == ["basis", "candidates", "status", "id", "ok", "reason"]
    flagged = DriveAnswer("currents", basis="b", candidates=("D1",), id="D1", ok=True, checks=(), status="ok",
                          unverified=True, unverified_reason="a transcription")
    assert list(flagged.to_dict())[-2:] == ["unverified", "unverified_reason"]


def test_a_regen_block_is_frozen() -> None:
    regen = Regen(0.0, 0.0, 0.0, 0.0, "none", 0.0, 0.0, 0.0, 0.0, None, None, False, None)
    with pytest.raises(dataclasses.FrozenInstanceError):
        regen.energy_per_cycle_J = 1.0  # type: ignore[misc]


@pytest.mark.parametrize("name", ["ball_screw", "z_axis", "hoist"])
def test_the_json_of_an_example_is_unchanged(name: str, capsys: pytest.CaptureFixture[str]) -> None:
    """``drivetrain size examples/NAME.yaml --json``, byte for byte, against the output saved before the blocks
    were typed (tests/data/json/NAME.json; the version keys, which change with every release and catalog
    update, left out). A change of a figure or a key here is a change of the documented JSON: say it in the
    CHANGELOG and save the files anew with ``python scripts/example_json.py`` (run with the code whose output is
    the reference)."""
    assert cli.main(["size", str(ROOT / "examples" / f"{name}.yaml"), "--json"]) in (0, 1)
    out = VOLATILE.sub("", capsys.readouterr().out)
    expected = (JSON_DATA / f"{name}.json").read_text(encoding="utf-8")
    assert '"regen": {' in expected and '"drive": {' in expected  # the typed blocks are in it
    assert out == expected
