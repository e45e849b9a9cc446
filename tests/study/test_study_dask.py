"""Studies on Dask: an embedded LocalCluster of two worker processes, and a real ``dask scheduler``
with two ``dask worker`` processes on loopback, started here on free ports and torn down.

Both must give the table the in-process run gives (same rows, same values).
"""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pandas as pd
import pytest
import yaml

from drivetrain.cli import main
from drivetrain.study import load_study, sweep
from drivetrain.study.runner import ENV_SCHEDULER, read_parquet

SRC = Path(__file__).parents[2] / "src"
BASE = Path(__file__).parents[2] / "examples" / "ball_screw.yaml"
GRID = {"study": 1, "name": "dask grid", "base": str(BASE),
        "parameters": {"mechanism.load.mass": {"start": "10 kg", "stop": "40 kg", "num": 4},
                       "mechanism.lead": {"values": [5, 10, 20], "unit": "mm"},
                       "profile[0].time": {"values": [0.4, 0.7], "unit": "s"}}}


@pytest.fixture(scope="module")
def study_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    p = tmp_path_factory.mktemp("study") / "grid.yaml"
    p.write_text(yaml.safe_dump(GRID, sort_keys=False), encoding="utf-8")
    return p


@pytest.fixture(scope="module")
def in_process(study_file: Path) -> pd.DataFrame:
    return sweep(study_file, workers=0).table


def _same(a: pd.DataFrame, b: pd.DataFrame) -> None:
    assert list(a["variant"]) == list(range(24))
    pd.testing.assert_frame_equal(a.reset_index(drop=True), b.reset_index(drop=True), check_dtype=False)


def test_local_cluster_two_processes(study_file: Path, in_process: pd.DataFrame) -> None:
    df = sweep(study_file, workers=2, batch=5).table
    _same(df, in_process)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="module")
def scheduler() -> Iterator[str]:
    """A dask scheduler and two single-threaded worker processes on loopback."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")])}
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    procs = [subprocess.Popen([sys.executable, "-m", "dask", "scheduler", "--host", "127.0.0.1", "--port", str(port),
                               "--no-dashboard"], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        from distributed import Client

        for _ in range(2):
            procs.append(subprocess.Popen([sys.executable, "-m", "dask", "worker", address, "--nthreads", "1",
                                           "--nworkers", "1", "--no-dashboard", "--host", "127.0.0.1"],
                                          env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        deadline = time.monotonic() + 60
        while True:
            try:
                with Client(address, timeout="5s") as client:
                    client.wait_for_workers(2, timeout=max(1.0, deadline - time.monotonic()))
                    break
            except OSError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.3)
        yield address
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            try:
                p.wait(timeout=3)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def test_existing_scheduler_two_workers(study_file: Path, in_process: pd.DataFrame, scheduler: str) -> None:
    df = sweep(study_file, scheduler=scheduler, batch=3).table
    _same(df, in_process)
    from distributed import Client

    with Client(scheduler, timeout="5s") as client:
        # both workers took part, and each loaded the catalog once (one engine per process)
        engines = client.run(lambda: __import__("drivetrain.study.runner", fromlist=["_ENGINE"])._ENGINE is not None)
        assert len(engines) == 2 and all(engines.values())


def test_scheduler_from_environment_cli(study_file: Path, in_process: pd.DataFrame, scheduler: str,
                                        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(ENV_SCHEDULER, scheduler)
    out = tmp_path / "env.parquet"
    assert main(["sweep", str(study_file), "-o", str(out), "--quiet"]) == 0
    df, _ = read_parquet(out)
    _same(df, in_process)


def test_unreachable_scheduler_is_input_error(study_file: Path, capsys: pytest.CaptureFixture[str],
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    from drivetrain.study import runner

    monkeypatch.setattr(runner, "CONNECT_TIMEOUT", "1s")
    port = _free_port()
    assert main(["sweep", str(study_file), "--scheduler", f"tcp://127.0.0.1:{port}", "--quiet", "-o",
                 str(study_file.with_name("x.parquet"))]) == 2
    assert capsys.readouterr().err.startswith("error: --scheduler")
    assert load_study(study_file).n_variants() == 24
