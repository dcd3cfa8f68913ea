"""The trial store never loses or silently changes data: foreign files refused untouched, damaged files and
read-only files reported in one line, a changed robot file refused (issue #16 section 1)."""

import os
import shutil
import sqlite3
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from sim.store import (
    APPLICATION_ID,
    COLUMNS,
    KEY_COLUMNS,
    SCHEMA,
    STORE_VERSION,
    RobotChangedError,
    StoreError,
    TrialStore,
    export_csv,
    read_rows,
)

REPO = Path(__file__).resolve().parents[2]


def _row(k: int, *, robot: str = "/robots/a.urdf", robot_hash: str = "h-a", error_len: int = 0) -> dict:
    """A complete trial row with key index ``k`` (the trial number)."""
    row = {c: None for c in COLUMNS}
    row.update(
        robot_hash=robot_hash,
        theta_w_deg=74.0,
        theta_l_deg=30.0,
        cv=0.1,
        phase=0.7,
        trial=k,
        duration_s=10.0,
        dt_s=5e-4,
        wing_period_s=2.0,
        leg_period_s=0.8,
        attempts=0,
        seed=1000 + k,
        status="ok",
        success=k % 2,
        time_to_right_s=1.5,
        attempt=1,
        mode="roll",
        phases=[0.7, 0.2],
        attempt_starts_s=[0.56, 2.56],
        robot=robot,
        version="0.1.0",
        error="x" * error_len,
        created_utc=f"2026-01-01T00:00:{k % 60:02d}+00:00",
    )
    return row


def _header(db: Path) -> tuple[int, int]:
    con = sqlite3.connect(db)
    try:
        return (
            con.execute("PRAGMA application_id").fetchone()[0],
            con.execute("PRAGMA user_version").fetchone()[0],
        )
    finally:
        con.close()


def test_new_store_is_marked(tmp_path):
    db = tmp_path / "new.sqlite"
    with TrialStore(db) as store:
        assert store.add(_row(0)) is True
        assert store.add(_row(0)) is False  # INSERT OR IGNORE: kept as it was
        assert store.count() == 1
    assert _header(db) == (APPLICATION_ID, STORE_VERSION) == (0x53524C54, 1)


def test_foreign_sqlite_file_is_refused_untouched(tmp_path):
    db = tmp_path / "other.sqlite"
    con = sqlite3.connect(db)
    con.execute("CREATE TABLE people (name TEXT)")
    con.execute("INSERT INTO people VALUES ('ada')")
    con.commit()
    con.close()
    before = db.read_bytes()
    with pytest.raises(StoreError, match=r"another application.*tables: people.*new --db"):
        TrialStore(db)
    assert db.read_bytes() == before  # no trials table, still in rollback-journal mode
    assert not Path(f"{db}-wal").exists()
    with pytest.raises(StoreError, match="another application"):
        read_rows(db)


def test_foreign_application_id_and_non_sqlite_files_are_refused(tmp_path):
    db = tmp_path / "app.sqlite"
    con = sqlite3.connect(db)
    con.execute("PRAGMA application_id = 1234")
    con.execute("CREATE TABLE trials (x)")
    con.commit()
    con.close()
    with pytest.raises(StoreError, match=r"application_id 0x4d2"):
        TrialStore(db)
    text = tmp_path / "notes.sqlite"
    text.write_text("not a database\n" * 200)
    with pytest.raises(StoreError, match="is not an SQLite database"):
        TrialStore(text)
    assert text.read_text() == "not a database\n" * 200


def test_store_of_todays_layout_without_marker_is_adopted(tmp_path):
    db = tmp_path / "legacy.sqlite"
    con = sqlite3.connect(db)
    con.execute("PRAGMA journal_mode = WAL")
    con.execute(SCHEMA)  # exactly the table today's code makes, no marker
    cols = ", ".join(COLUMNS)
    for k, h in ((0, "h-old"), (1, "h-new")):  # the same robot file, swept twice with different contents
        r = _row(k, robot_hash=h)
        r["phases"] = r["attempt_starts_s"] = "[]"
        con.execute(
            f"INSERT INTO trials ({cols}) VALUES ({', '.join('?' * len(COLUMNS))})", [r[c] for c in COLUMNS]
        )
    con.commit()
    con.close()
    assert _header(db) == (0, 0)
    assert len(read_rows(db)) == 2 and _header(db) == (0, 0)  # reading does not write
    with TrialStore(db) as store:
        assert store.count() == 2
        assert store.robots() == {"/robots/a.urdf": "h-new"}  # the hash of its latest trial
        with pytest.raises(RobotChangedError):
            store.check_robot("/robots/a.urdf", "h-old")
    assert _header(db) == (APPLICATION_ID, STORE_VERSION)


def test_trials_table_of_another_layout_is_refused(tmp_path):
    db = tmp_path / "extra.sqlite"
    con = sqlite3.connect(db)
    con.execute(SCHEMA.replace("created_utc TEXT", "created_utc TEXT, patient TEXT"))
    con.commit()
    con.close()
    with pytest.raises(StoreError, match="extra column patient"):
        TrialStore(db)
    assert _header(db) == (0, 0)


def test_changed_robot_file_is_refused(tmp_path):
    db = tmp_path / "robots.sqlite"
    with TrialStore(db) as store:
        assert store.add(_row(0))
        assert store.add(_row(0, robot="/robots/b.urdf", robot_hash="h-b"))  # another robot file is its own
    with TrialStore(db) as store:
        with pytest.raises(RobotChangedError, match=r"a\.urdf' changed.*h-a.*h-a2.*new --db, or restore"):
            store.add(_row(1, robot_hash="h-a2"))
        assert store.count() == 2
        with pytest.raises(StoreError):  # RobotChangedError is a StoreError, a ValueError
            store.check_robot("/robots/b.urdf", "h-b2")
        store.check_robot("/robots/a.urdf", "h-a")


def _damaged_store(tmp_path) -> Path:
    db = tmp_path / "damaged.sqlite"
    with TrialStore(db) as store:
        for k in range(300):
            store.add(_row(k, error_len=400))
    # the last connection checkpoints the write-ahead log into the file and removes it
    assert not Path(f"{db}-wal").exists()
    size = db.stat().st_size
    assert size > 40 * 4096
    with open(db, "r+b") as f:  # keep the header page, overwrite pages 3.. of the table with noise
        f.seek(2 * 4096)
        f.write(bytes(range(256)) * (size // 256 - 20))
    return db


@pytest.mark.parametrize("op", ["count", "rows", "done_keys", "integrity", "add", "has"])
def test_damaged_store_gives_one_store_error(tmp_path, op):
    db = _damaged_store(tmp_path)
    calls = {
        "count": lambda s: s.count(),
        "rows": lambda s: s.rows(),
        "done_keys": lambda s: s.done_keys(),
        "integrity": lambda s: s.integrity_ok() and s.rows(),
        "add": lambda s: [s.add(_row(k)) for k in range(300, 400)],
        "has": lambda s: [s.has(_row(k)[c] for c in KEY_COLUMNS) for k in range(300)] and s.rows(),
    }
    with pytest.raises(StoreError, match=r"damaged.*restore it from a backup") as info:
        with TrialStore(db) as store:
            calls[op](store)
    assert str(db) in str(info.value) and "\n" not in str(info.value)


def test_damaged_store_export_and_read_give_store_error(tmp_path):
    db = _damaged_store(tmp_path)
    with pytest.raises(StoreError, match="damaged"):
        read_rows(db)
    with pytest.raises(StoreError, match="damaged"):
        export_csv(db, tmp_path / "out.csv")


READ_ONLY_SCRIPT = """
import sys
from sim.store import StoreError, TrialStore, read_rows
db = sys.argv[1]
try:
    TrialStore(db)
except StoreError as exc:
    print("write:", exc)
print("read:", len(read_rows(db)))
"""


def _as_unprivileged(args: list[str]) -> subprocess.CompletedProcess:
    """Run python ``args`` as a user for whom the files made here are read-only (root ignores permissions)."""
    cmd = [sys.executable, *args]
    if os.geteuid() == 0:
        setpriv = shutil.which("setpriv")
        if setpriv is None:
            pytest.skip("running as root without setpriv: cannot make a file read-only")
        cmd = [setpriv, "--reuid=65534", "--regid=65534", "--clear-groups", *cmd]
    env = {**os.environ, "PYTHONPATH": str(REPO), "PYTHONDONTWRITEBYTECODE": "1"}
    return subprocess.run(cmd, capture_output=True, text=True, timeout=120, env=env, cwd="/")


@pytest.mark.parametrize("read_only", ["file", "directory"])
def test_read_only_database_says_not_writable_and_still_reads(read_only):
    top = Path(tempfile.mkdtemp(prefix="store-ro-"))  # pytest's tmp_path is private to its user
    try:
        os.chmod(top, 0o755)
        db = top / "trials.sqlite"
        with TrialStore(db) as store:
            for k in range(3):
                store.add(_row(k))
        os.chmod(db, 0o444)
        os.chmod(top, 0o555 if read_only == "directory" else 0o777)
        out = _as_unprivileged(["-c", READ_ONLY_SCRIPT, str(db)])
    finally:
        os.chmod(top, 0o755)
        shutil.rmtree(top)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0].startswith(f"write: database '{db}' is not writable (read-only ")
    assert "chmod u+w" in lines[0] and "another --db" in lines[0]
    assert lines[1] == "read: 3"
