"""Parse time of the largest and deepest YAML texts the input bounds admit or refuse (docs/limits.md).

Each text is parsed by ``drivetrain.axis.yaml_text.parse_yaml`` a few times; the table gives the best
wall time and the outcome (the data, or the bound that refused it). Run: ``python bench/bench_yaml_bounds.py``.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from drivetrain.axis.yaml_text import MAX_DEPTH, MAX_NODES, parse_yaml
from drivetrain.errors import InputError


def cases() -> list[tuple[str, Callable[[], str]]]:
    return [
        ("flow mapping nested 20,000 deep (80 kB)", lambda: "{a: " * 20_000 + "1" + "}" * 20_000),
        ("flow list nested 100,000 deep", lambda: "[" * 100_000 + "]" * 100_000),
        ("1 MB: 95 levels, then 150,000 values (refused)",
         lambda: "{a: " * 95 + "[" + ",".join(["1"] * 150_000) + "]" + "}" * 95),
        (f"0.8 MB: 95 levels, then {MAX_NODES - 10_000:,} values (admitted)",
         lambda: "{a: " * 95 + "[" + ",".join(["12345678"] * (MAX_NODES - 10_000)) + "]" + "}" * 95),
        ("flat list of 330,000 values (0.66 MB, refused)", lambda: "[" + ",".join(["1"] * 330_000) + "]"),
        (f"block mappings {MAX_DEPTH} deep (admitted)",
         lambda: "".join("  " * d + "k:\n" for d in range(MAX_DEPTH - 1)) + "  " * (MAX_DEPTH - 1) + "k: 1\n"),
    ]


def main(repeat: int = 3) -> None:
    print(f"| text | best of {repeat} | outcome |")
    print("|---|---|---|")
    for name, make in cases():
        text = make()
        best = float("inf")
        outcome = ""
        for _ in range(repeat):
            t0 = time.perf_counter()
            try:
                parse_yaml(text)
                outcome = "parsed"
            except InputError as exc:
                outcome = exc.rule
            best = min(best, time.perf_counter() - t0)
        print(f"| {name} | {best * 1000:.0f} ms | {outcome} |")


if __name__ == "__main__":
    main()
