"""Regenerate the report pictures in docs/: one example report per mechanism family.

For each family (ball screw, belt, rack and pinion, rotary indexing table, hoist) this sizes the
shipped example, writes its HTML report, opens it in headless Debian Chromium through
Playwright and saves a screenshot of the top of the page at 1280 px width as
``docs/report-<family>.png``; the example machine's report becomes ``docs/machine-report.png``.

    .venv/bin/python scripts/make_report_images.py            # all families into docs/
    .venv/bin/python scripts/make_report_images.py --keep-html out/   # also keep the HTML reports

Needs /usr/bin/chromium (``make browser`` installs it); Playwright's own browser download is
not used. The report date is the last commit's date unless SOURCE_DATE_EPOCH is set, so the
pictures only change when the reports do.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FAMILIES: dict[str, str] = {
    "ball-screw": "ball_screw.yaml",
    "belt": "belt.yaml",
    "rack-pinion": "rack_pinion.yaml",
    "rotary": "rotary.yaml",
    "hoist": "hoist.yaml",
}
"""docs picture name -> example axis file."""
MACHINE = "machine/pick_and_place.yaml"
"""the example machine, pictured as docs/machine-report.png"""
CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run"]


def _commit_epoch() -> str | None:
    try:
        out = subprocess.run(["git", "-C", str(ROOT), "log", "-1", "--format=%ct"], capture_output=True, text=True,
                             check=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    value = out.stdout.strip()
    return value if value.isdigit() else None


def write_reports(folder: Path, units: str = "si") -> dict[str, Path]:
    """Size every family's example and write its HTML report into ``folder``."""
    from drivetrain import size
    from drivetrain.report import write_report

    paths = {}
    for name, example in FAMILIES.items():
        result = size(ROOT / "examples" / example)
        paths[name] = write_report(result, folder / f"report-{name}.html", units=units)
    from drivetrain import size_machine
    from drivetrain.report.machine import write_machine_report

    paths["machine"] = write_machine_report(size_machine(ROOT / "examples" / MACHINE), folder / "machine-report.html")
    return paths


def screenshot(reports: dict[str, Path], out: Path, width: int, height: int) -> list[Path]:
    """Screenshot the top ``height`` px of each report at ``width`` px into ``out``."""
    from playwright.sync_api import sync_playwright

    written = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": width, "height": height}, device_scale_factor=1)
            for name, html in reports.items():
                page.goto(html.resolve().as_uri())
                page.wait_for_function("document.querySelectorAll('.dt-plot .main-svg').length >= "
                                       "document.querySelectorAll('.dt-plot').length")
                target = out / ("machine-report.png" if name == "machine" else f"report-{name}.png")
                page.screenshot(path=str(target), full_page=False)
                written.append(target)
        finally:
            browser.close()
    return written


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "docs", help="folder of the pictures (default docs/)")
    parser.add_argument("--width", type=int, default=1280, help="page width in px (default 1280)")
    parser.add_argument("--height", type=int, default=1300, help="height of the picture in px (default 1300)")
    parser.add_argument("--keep-html", type=Path, default=None, help="also keep the HTML reports in this folder")
    args = parser.parse_args(argv)
    if not Path(CHROMIUM).exists():
        print(f"error: {CHROMIUM} not found; install Debian's chromium (make browser)", file=sys.stderr)
        return 2
    if "SOURCE_DATE_EPOCH" not in os.environ and (epoch := _commit_epoch()):
        os.environ["SOURCE_DATE_EPOCH"] = epoch
    args.out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.keep_html or Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        for path in screenshot(write_reports(folder), args.out, args.width, args.height):
            print(f"wrote {path.relative_to(ROOT) if path.is_relative_to(ROOT) else path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
