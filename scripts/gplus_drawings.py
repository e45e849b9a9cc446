"""Add the G+ vendor drawings' data to gearboxes_planetary.csv (data/SOURCES.md, "G+ drawings").

Usage: python scripts/gplus_drawings.py GIT_DIR   (run once, on the file as of data version 2026.11-1)
GIT_DIR is a clone of github.com/urchacha/gearbox-configurator at commit a616618 (the drawings
are vendor drawing sheets of GIGA Precision Technology Co., Ltd.). Needs ``pdftotext`` (poppler).

Per model and stage it reads every drawing sheet's text: the specification code in the title
block (model-stage-(bore-pilot-bolt circle or square-screw)), the rated and maximum input speed,
the emergency-stop rule and the rated output torque table. It then fills, per CSV row:
input_bore_min/max (smallest and largest drawn input bore), input_pilot (where every drawn
adapter has the same pilot), input_adapters (every drawn adapter), the source_* document columns
and verified = no (inertia, mass, stiffness and noise are not printed on the drawings; T2B is
not printed at all), and it notes each place where the drawing disagrees with the row.
"""

from __future__ import annotations

import csv
import re
import subprocess
import sys
import tempfile
import urllib.parse
from pathlib import Path

COMMIT = "a616618b206f66391d37f0485a3f89cb9b93a427"
REPO_URL = f"https://github.com/urchacha/gearbox-configurator/blob/{COMMIT}/"
CSV_PATH = Path(__file__).resolve().parents[1] / "src/drivetrain/catalog/data/gearboxes_planetary.csv"
MARK = "drawing sheets: "
SPEC = re.compile(r"^(GP[A-Z]*\d+-L\d)-\((\d+(?:\.\d+)?)-(\d+(?:\.\d+)?)-(□?)(\d+(?:\.\d+)?)-(M\d+)\)$")


def drawing_texts(git_dir: Path) -> dict[str, tuple[str, str]]:
    """spec code -> (repository path, pdftotext -layout text) of every GP* drawing sheet."""
    names = subprocess.run(
        ["git", "-C", str(git_dir), "ls-tree", "-r", "--name-only", "-z", COMMIT, "public/drawings/pdf/"],
        capture_output=True,
        check=True,
    ).stdout.decode().split("\0")
    out: dict[str, tuple[str, str]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for path in names:
            if not path.upper().endswith(".PDF") or not path.split("/")[3].startswith("GP"):
                continue
            pdf = Path(tmp) / "d.pdf"
            pdf.write_bytes(subprocess.run(["git", "-C", str(git_dir), "show", f"{COMMIT}:{path}"],
                                           capture_output=True, check=True).stdout)
            text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True, check=True).stdout
            out[Path(path).stem] = (path, text.decode("utf-8", "replace"))
    return out


def read_sheet(text: str) -> dict[str, object]:
    """Rated/max input speed [rpm], ratio -> rated output torque [N m], e-stop rule, from one sheet."""
    rpm = [int(x) for x in re.findall(r"(\d+)\s*rpm", text)]
    lines = text.splitlines()
    table: dict[float, float] = {}
    for i, line in enumerate(lines):
        if "减速比" in line:
            ratios = [float(x) for x in re.findall(r"(?<![\d.])(\d+(?:\.\d+)?)(?![\d.])", line.split("比", 1)[1])]
            for nxt in lines[i + 1 : i + 8]:
                torques = [float(x) for x in re.findall(r"(\d+(?:\.\d+)?)\s*Nm", nxt)]
                if len(torques) >= 2:
                    if len(torques) == len(ratios):
                        table = dict(zip(ratios, torques, strict=True))
                    break
    return {
        "rpm": rpm if len(rpm) == 2 else [],
        "table": table,
        "estop3": "3 times rated output torque" in text,
        "title": bool(re.search(r"GIGA Precision Technology", text)),
    }


def fmt(x: float) -> str:
    return f"{x:g}"


def main(git_dir: Path) -> None:
    sheets = drawing_texts(git_dir)
    with CSV_PATH.open(encoding="utf-8", newline="") as fh:
        reader = csv.DictReader(fh)
        fields = list(reader.fieldnames or [])
        rows = list(reader)
    for col in ("input_bore_min_mm", "input_pilot_mm", "input_flange_mm", "input_adapters", "verified",
                "source_document", "source_section", "source_page", "source_url"):
        if col not in fields:
            fields.append(col)
    for r in rows:
        model = r["id"].rsplit("-", 1)[0]
        ratio = float(r["ratio"])
        mine = sorted(s for s in sheets if s.startswith(model + "-("))
        adapters = [m for s in mine if (m := SPEC.match(s))]
        # earlier notes this script supersedes: the drawing's torque and speeds are now taken
        stale = ("drawing table lists", "source value kept", MARK)
        notes = [n for n in r["notes"].split("; ") if n and not n.startswith(stale)]
        found: list[str] = []
        r["input_flange_mm"] = ""
        if not adapters:
            r.update(input_bore_min_mm="", input_pilot_mm="", input_adapters="", source_document="",
                     source_section="", source_page="", source_url="", verified="no")
            notes.append(MARK + "none for this model and stage in the source; input bore is the "
                         "configurator's value, not confirmed; no vendor document found (data/SOURCES.md)")
            r["notes"] = "; ".join(notes)
            continue
        bores = [float(m.group(2)) for m in adapters]
        pilots = {float(m.group(3)) for m in adapters}
        r["input_bore_min_mm"] = fmt(min(bores))
        old_bore = r["input_bore_max_mm"]
        r["input_bore_max_mm"] = fmt(max(bores))
        if old_bore and float(old_bore) != max(bores):
            found.append(f"input bore max {fmt(max(bores))} mm (configurator {old_bore} mm)")
        r["input_pilot_mm"] = fmt(next(iter(pilots))) if len(pilots) == 1 else ""
        r["input_adapters"] = " ".join(
            f"{m.group(2)}/{m.group(3)}/{'sq' if m.group(4) else ''}{m.group(5)}/{m.group(6)}" for m in adapters
        )
        read = [read_sheet(sheets[s][1]) for s in mine]
        checked = []
        rpm = next((x["rpm"] for x in read if x["rpm"]), [])
        if rpm:
            n1n, n1max = rpm
            if float(r["rated_input_speed_rpm"]) != n1n:
                found.append(f"rated input speed {n1n} rpm taken (configurator {r['rated_input_speed_rpm']} rpm)")
                r["rated_input_speed_rpm"] = str(n1n)
            else:
                checked.append("n1N")
            if r["max_input_speed_rpm"] and float(r["max_input_speed_rpm"]) != n1max:
                found.append(f"max input speed {n1max} rpm taken (row had {r['max_input_speed_rpm']} rpm)")
                r["max_input_speed_rpm"] = str(n1max)
                notes = [n for n in notes if n != "max input speed from drawing"]
            elif not r["max_input_speed_rpm"]:
                r["max_input_speed_rpm"] = str(n1max)
                checked.append("n1max (from drawing)")
            else:
                checked.append("n1max")
        t2n = next((x["table"][ratio] for x in read if ratio in x["table"]), None)  # type: ignore[index,operator]
        if t2n is None:
            found.append("its torque table has no value for this ratio")
        elif abs(t2n - float(r["rated_output_torque_Nm"])) > 1e-9:
            found.append(f"rated output torque {fmt(t2n)} N*m taken (configurator {r['rated_output_torque_Nm']} N*m)")
            r["rated_output_torque_Nm"] = fmt(t2n)
            if r["emergency_stop_torque_Nm"] and any(x["estop3"] for x in read):
                r["emergency_stop_torque_Nm"] = fmt(3 * t2n)
        else:
            checked.append("T2N")
        checked.append("input bore")
        found.append("confirm " + ", ".join(checked) + "; not verified: inertia, mass, torsional "
                     "stiffness and noise are the configurator's per-model values (not on the drawings); "
                     "T2B is not printed on the drawings")
        notes.append(MARK + ", ".join(found))
        r["notes"] = "; ".join(notes)
        r["verified"] = "no"
        r["source_document"] = (
            "GIGA Precision Technology Co., Ltd., Precision Planetary Gear Reducer drawing sheets "
            + ", ".join(mine) + " (rev. 00, 2021-2-1)"
        )
        r["source_section"] = "specification table and title block"
        r["source_page"] = "1 (single sheet)"
        r["source_url"] = " ".join(REPO_URL + urllib.parse.quote(sheets[s][0], safe="/()-.") for s in mine)
    with CSV_PATH.open("w", encoding="utf-8", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=fields, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)


if __name__ == "__main__":
    main(Path(sys.argv[1]))
