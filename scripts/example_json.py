"""Save the ``--json`` of the examples that tests/sizing/test_typed_blocks.py and tests/sizing/test_typed_answer.py
compare byte for byte: ``python scripts/example_json.py [FOLDER]`` (default tests/data/json).

Each file is ``drivetrain size examples/NAME.yaml --json`` less the two version lines (``drivetrain_version``,
``catalog_version``), run with a temporary data folder, so no user catalog is read. Run it with the code whose
output is the reference (the code before a change that must not change the JSON), then the test with the
changed code.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ("ball_screw", "z_axis", "hoist", "conveyor", "belt_gantry_3m", "belt_dynamic", "lead_screw", "rack_pinion")
VOLATILE = re.compile(r'^  "(drivetrain_version|catalog_version)": .*\n', re.MULTILINE)


def main(folder: Path) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        os.environ.pop("DRIVETRAIN_CATALOG", None)
        os.environ["DRIVETRAIN_DATA_DIR"] = str(Path(tmp) / "data")
        os.environ["DRIVETRAIN_CACHE_DIR"] = str(Path(tmp) / "cache")
        from drivetrain import cli

        folder.mkdir(parents=True, exist_ok=True)
        for name in EXAMPLES:
            out = io.StringIO()
            with contextlib.redirect_stdout(out):
                cli.main(["size", str(ROOT / "examples" / f"{name}.yaml"), "--json"])
            (folder / f"{name}.json").write_text(VOLATILE.sub("", out.getvalue()), encoding="utf-8")
            print(folder / f"{name}.json")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "tests" / "data" / "json")
