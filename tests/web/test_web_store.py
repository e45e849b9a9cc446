"""The project store: history and undo, and durability: a process killed (SIGKILL) in the middle of
a stream of saves leaves a consistent database holding every save acknowledged before the kill."""

from __future__ import annotations

import os
import random
import re
import signal
import sqlite3
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest

from drivetrain.web.store import DB_NAME, Conflict, NotFound, Store, StoreError

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL")


def text_of(i: int, size: int = 0) -> str:
    return f"axis: save {i}\nmechanism: {{type: rotary}}\n# {'x' * size}\n"


def test_history_undo_and_restore(tmp_path: Path) -> None:
    store = Store(tmp_path)
    p = store.create("A", text_of(1))
    assert store.save(p.id, text_of(2), base_version=1).version == 2
    assert store.save(p.id, text_of(2)).version == 2  # same text: no new version
    with pytest.raises(Conflict):
        store.save(p.id, text_of(3), base_version=1)
    assert store.save(p.id, text_of(3)).version == 3
    undone = store.undo(p.id)
    assert undone.version == 4 and store.head(p.id)[1].text == text_of(2)
    assert store.undo(p.id).version == 5 and store.head(p.id)[1].text == text_of(1)
    with pytest.raises(Conflict):
        store.undo(p.id)
    assert store.save(p.id, text_of(9)).version == 6
    assert store.undo(p.id).version == 7 and store.head(p.id)[1].text == text_of(1)
    assert [v.version for v in store.versions(p.id)] == [7, 6, 5, 4, 3, 2, 1]
    assert store.restore(p.id, 3).version == 8 and store.head(p.id)[1].text == text_of(3)
    copy = store.duplicate(p.id)
    assert copy.name == "A (copy)" and store.head(copy.id)[1].text == text_of(3)
    store.rename(p.id, "  B   renamed ")
    assert store.info(p.id).name == "B renamed"
    store.delete(p.id)
    with pytest.raises(NotFound):
        store.info(p.id)
    with pytest.raises(NotFound):
        store.version(p.id, 1)
    assert [q.id for q in store.projects()] == [copy.id]
    for bad in ("", "   ", "x" * 201, "nul\x00here"):
        with pytest.raises(StoreError):
            store.create(bad, "a: 1")


def test_wal_mode_and_full_sync(tmp_path: Path) -> None:
    store = Store(tmp_path)
    store.create("A", text_of(1))
    conn = sqlite3.connect(tmp_path / DB_NAME)
    try:
        assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    finally:
        conn.close()
    with store._connect() as c:
        assert c.execute("PRAGMA synchronous").fetchone()[0] == 2  # FULL
    assert store.integrity() == "ok"


def check_acknowledged(directory: Path, acked: dict[int, dict[int, str]]) -> int:
    """The database is consistent and holds every acknowledged (project, version, text); returns the count."""
    conn = sqlite3.connect(directory / DB_NAME)
    try:
        assert conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"
        assert conn.execute("PRAGMA foreign_key_check").fetchall() == []
        heads = dict(conn.execute("SELECT id, head FROM projects").fetchall())
        for pid, head in heads.items():
            versions = [r[0] for r in conn.execute("SELECT version FROM versions WHERE project_id = ? ORDER BY version",
                                                   (pid,))]
            assert versions == list(range(1, head + 1)), f"project {pid}: versions {versions[-5:]} head {head}"
        count = 0
        for pid, saves in acked.items():
            assert pid in heads, f"acknowledged project {pid} is missing"
            for version, text in saves.items():
                row = conn.execute("SELECT text FROM versions WHERE project_id = ? AND version = ?",
                                   (pid, version)).fetchone()
                assert row is not None, f"acknowledged save {pid}/{version} is missing"
                assert row[0] == text
                count += 1
        return count
    finally:
        conn.close()


WRITER = textwrap.dedent("""
    import sys
    from pathlib import Path
    from drivetrain.web.store import Store

    def text_of(i, size):
        return f"axis: save {i}\\nmechanism: {{type: rotary}}\\n# {'x' * size}\\n"

    store = Store(Path(sys.argv[1]))
    pids = [store.create(f"p{k}", text_of(0, 10)).id for k in range(3)]
    for pid in pids:
        print(f"ack {pid} 1 0", flush=True)
    i = 0
    while True:
        i += 1
        pid = pids[i % 3]
        size = (i * 7919) % 200_000
        info = store.save(pid, text_of(i, size))
        print(f"ack {pid} {info.version} {i} {size}", flush=True)
""")


@pytest.mark.parametrize("seed", [1, 2])
def test_sigkill_during_a_stream_of_saves_loses_no_acknowledged_save(tmp_path: Path, seed: int) -> None:
    rng = random.Random(seed)
    proc = subprocess.Popen([sys.executable, "-c", WRITER, str(tmp_path)], stdout=subprocess.PIPE, text=True,
                            env={**os.environ, "PYTHONUNBUFFERED": "1"})
    acked: dict[int, dict[int, str]] = {}
    lines: list[str] = []

    def reader() -> None:
        assert proc.stdout is not None
        for line in proc.stdout:
            lines.append(line)

    t = threading.Thread(target=reader, daemon=True)
    t.start()
    deadline = time.monotonic() + 30
    while len(lines) < 40 + rng.randrange(40) and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.001)
    time.sleep(rng.random() * 0.02)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=10)
    t.join(timeout=10)
    assert proc.returncode == -signal.SIGKILL
    for line in lines:
        parts = line.split()
        pid, version, i = int(parts[1]), int(parts[2]), int(parts[3])
        size = int(parts[4]) if len(parts) > 4 else 10
        acked.setdefault(pid, {})[version] = text_of(i, size)
    assert sum(len(v) for v in acked.values()) >= 40
    assert check_acknowledged(tmp_path, acked) >= 40
    Store(tmp_path).save(min(acked), text_of(-1))  # still writable after recovery


def test_killing_the_server_mid_stream_loses_no_acknowledged_save(tmp_path: Path) -> None:
    httpx = pytest.importorskip("httpx")
    pytest.importorskip("uvicorn")
    proc = subprocess.Popen(
        [sys.executable, "-m", "drivetrain.cli", "serve", "--port", "0", "--data-dir", str(tmp_path)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    try:
        assert proc.stdout is not None
        first = proc.stdout.readline()
        m = re.search(r"http://127\.0\.0\.1:(\d+)/", first)
        assert m, first + (proc.stderr.read() if proc.stderr else "")
        url = m.group(0).rstrip("/")
        acked: dict[int, dict[int, str]] = {}
        errors: list[str] = []
        stop = threading.Event()

        def client(k: int) -> None:
            with httpx.Client(base_url=url, timeout=10) as c:
                r = c.post("/api/projects", json={"name": f"stream {k}", "yaml": text_of(0)})
                pid = r.json()["id"]
                acked.setdefault(pid, {})[1] = text_of(0)
                i = 0
                while not stop.is_set():
                    i += 1
                    text = text_of(i, (i * 104729) % 20_000)
                    try:
                        r = c.put(f"/api/projects/{pid}", json={"yaml": text})
                    except httpx.HTTPError:
                        return  # the server died: this save was never acknowledged
                    if r.status_code != 200:
                        errors.append(r.text)
                        return
                    acked[pid][r.json()["version"]] = text

        threads = [threading.Thread(target=client, args=(k,), daemon=True) for k in range(3)]
        for th in threads:
            th.start()
        deadline = time.monotonic() + 20
        while sum(len(v) for v in acked.values()) < 60 and time.monotonic() < deadline:
            time.sleep(0.01)
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=10)
        stop.set()
        for th in threads:
            th.join(timeout=10)
        assert not errors, errors[:3]
        snapshot = {pid: dict(v) for pid, v in acked.items()}
        assert check_acknowledged(tmp_path, snapshot) >= 60
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait(timeout=10)


def test_machine_projects_keep_their_kind_and_history(tmp_path: Path) -> None:
    store = Store(tmp_path)
    axis = store.create("X", text_of(1))
    machine = store.create("M", "version: 1\naxes: []\n", kind="machine")
    assert (axis.kind, machine.kind) == ("axis", "machine")
    assert store.save(machine.id, "version: 1\naxes: [{project: 1}]\n").kind == "machine"
    assert store.undo(machine.id).kind == "machine" and store.head(machine.id)[1].text == "version: 1\naxes: []\n"
    assert store.duplicate(machine.id).kind == "machine"
    assert [p.name for p in store.projects("machine")] == ["M (copy)", "M"]
    assert [p.name for p in store.projects("axis")] == ["X"]
    with pytest.raises(StoreError) as err:
        store.create("Q", "a: 1", kind="gearbox")
    assert err.value.field == "kind"


def test_a_schema_1_database_is_upgraded_in_place(tmp_path: Path) -> None:
    """A project database written before kinds existed: its projects become axis projects, nothing lost."""
    conn = sqlite3.connect(tmp_path / DB_NAME)
    conn.executescript("""
        CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
        CREATE TABLE projects (id INTEGER PRIMARY KEY AUTOINCREMENT, name TEXT NOT NULL, created REAL NOT NULL,
                               updated REAL NOT NULL, head INTEGER NOT NULL);
        CREATE TABLE versions (project_id INTEGER NOT NULL REFERENCES projects(id) ON DELETE CASCADE,
                               version INTEGER NOT NULL, created REAL NOT NULL, text TEXT NOT NULL,
                               restored_from INTEGER, note TEXT NOT NULL DEFAULT '',
                               PRIMARY KEY (project_id, version));
        INSERT INTO meta VALUES ('schema_version', '1');
        INSERT INTO projects VALUES (1, 'old axis', 1.0, 2.0, 2);
        INSERT INTO versions VALUES (1, 1, 1.0, 'axis: v1', NULL, 'created');
        INSERT INTO versions VALUES (1, 2, 2.0, 'axis: v2', NULL, '');
    """)
    conn.close()
    store = Store(tmp_path)
    (old,) = store.projects()
    assert (old.name, old.version, old.kind) == ("old axis", 2, "axis")
    assert [v.text for v in store.versions(1)] == ["axis: v2", "axis: v1"]
    assert store.create("M", "version: 1", kind="machine").kind == "machine"
    assert Store(tmp_path).projects("machine")[0].name == "M"
    conn = sqlite3.connect(tmp_path / DB_NAME)
    assert conn.execute("SELECT value FROM meta WHERE key = 'schema_version'").fetchone()[0] == "2"
    conn.close()
    assert store.integrity() == "ok"
