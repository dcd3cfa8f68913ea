"""SQLite store of trial results: one row per trial, keyed by every parameter and the seed.

The database runs in WAL mode with a 60 s busy timeout, so several sweeps (processes) can append to one file at
once; each result is committed on its own as it arrives (``INSERT OR IGNORE``: a trial that another sweep
already stored is kept as it was), so killing a sweep loses at most the trials still running.

Nothing but a trial store is written to: a new store is marked (``PRAGMA application_id`` ``APPLICATION_ID`` and
``user_version`` ``STORE_VERSION``); an SQLite file without the mark is refused unless it holds exactly the
``trials`` table of the layout made before the mark existed (it is then marked). The store keeps, per robot
file, the description hash it was swept with and refuses to add trials of a changed file. Every SQLite error
(a damaged file, a read-only file, a lock held too long) becomes a one-line :class:`StoreError` naming the file
and what to do. ``TrialStore(path, readonly=True)`` and :func:`read_rows` read without writing anything.

It is one concept, the trial database (schema, writes, reads, resume), hence its length.
"""

from __future__ import annotations

import csv
import json
import os
import sqlite3
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path

from geometry.errors import UsageError

KEY_COLUMNS = (
    "robot_hash",
    "theta_w_deg",
    "theta_l_deg",
    "cv",
    "phase",
    "trial",
    "duration_s",
    "dt_s",
    "wing_period_s",
    "leg_period_s",
    "attempts",
    "seed",
)
"""Every parameter of a trial; ``attempts`` 0 means "as many as fit in ``duration_s``"."""
RESULT_COLUMNS = (
    "success",
    "time_to_right_s",
    "attempt",
    "mode",
    "phases",
    "attempt_starts_s",
    "sim_s",
    "wall_s",
    "cpu_s",
    "max_tracking_error_deg",
    "model_hash",
)
"""What a finished trial stores from its :class:`sim.trial.TrialResult` (``TrialResult.to_dict`` keys)."""
COLUMNS = KEY_COLUMNS + (
    "status",
    *RESULT_COLUMNS,
    "robot",
    "version",
    "error",
    "created_utc",
    "model_set",
    "model_set_hash",
    "side",
    "engine",
)
"""``model_set``/``model_set_hash``: the model parameter set (:mod:`sim.model_set`; the hash is that of the set in
the trial's engine); a store made before sets existed gets both columns with the ``paper`` set's values (the only
model then) when opened for writing. ``side``: the roll sign a righted trial rolled over to
(:class:`sim.trial.TrialResult`); NULL in trials stored before it was recorded. ``engine``: the physics engine
(:data:`sim.engine.ENGINES`); a store made before engines existed holds pybullet trials."""
LATE_COLUMNS = ("model_set", "model_set_hash", "side", "engine")
"""Columns added after the first layout: an older store gets them when opened for writing (read-only: read as
NULL); a missing ``model_set``/``model_set_hash`` means the ``paper`` set, a missing ``side`` is unknown, a missing
``engine`` is pybullet."""
_TYPES = {
    "robot_hash": "TEXT NOT NULL",
    "theta_w_deg": "REAL NOT NULL",
    "theta_l_deg": "REAL NOT NULL",
    "cv": "REAL NOT NULL",
    "phase": "REAL NOT NULL",
    "trial": "INTEGER NOT NULL",
    "duration_s": "REAL NOT NULL",
    "dt_s": "REAL NOT NULL",
    "wing_period_s": "REAL NOT NULL",
    "leg_period_s": "REAL NOT NULL",
    "attempts": "INTEGER NOT NULL",
    "seed": "INTEGER NOT NULL",
    "status": "TEXT NOT NULL",
    "success": "INTEGER",
    "time_to_right_s": "REAL",
    "attempt": "INTEGER",
    "mode": "TEXT",
    "phases": "TEXT",
    "attempt_starts_s": "TEXT",
    "sim_s": "REAL",
    "wall_s": "REAL",
    "cpu_s": "REAL",
    "max_tracking_error_deg": "REAL",
    "model_hash": "TEXT",
    "robot": "TEXT",
    "version": "TEXT",
    "error": "TEXT",
    "created_utc": "TEXT",
    "model_set": "TEXT",
    "model_set_hash": "TEXT",
    "side": "INTEGER",
    "engine": "TEXT",
}
SCHEMA = (
    "CREATE TABLE IF NOT EXISTS trials ("
    + ", ".join(f"{c} {_TYPES[c]}" for c in COLUMNS)
    + f", PRIMARY KEY ({', '.join(KEY_COLUMNS)}))"
)


APPLICATION_ID = 0x53524C54
"""``PRAGMA application_id`` of a trial store (ASCII "SRLT"), written when the store is created: a SQLite file
without it is another application's and is refused, not written to."""
STORE_VERSION = 1
"""``PRAGMA user_version`` of the current layout: the ``trials`` table and the ``robots`` table (the description
hash each robot file was swept with)."""
ROBOTS_SCHEMA = (
    "CREATE TABLE IF NOT EXISTS robots (robot TEXT PRIMARY KEY, robot_hash TEXT NOT NULL, "
    "created_utc TEXT NOT NULL)"
)
_DAMAGED = (
    "'{path}' is damaged ({what}); restore it from a backup, or copy what is readable into a new file "
    "with the sqlite3 shell's .recover command, and sweep into a new --db"
)


class StoreError(UsageError):
    """The file is not a usable trial database (absent, another application's, another layout, damaged,
    read-only, or swept with another version of a robot file)."""


class RobotChangedError(StoreError):
    """The robot file of a sweep hashes differently from when its trials in this database were run."""


def _now_utc() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="seconds")


def _sqlite_code(exc: sqlite3.Error) -> str:
    return getattr(exc, "sqlite_errorname", "") or ""


class TrialStore:
    """A trial database; use as a context manager.

    Parameters
    ----------
    path : path
        SQLite file. Opened for appending it is created when absent (with the trial store's application id and
        layout version); opened ``readonly`` it must exist.
    timeout_s : float
        How long to wait for another process's write lock, s.
    readonly : bool
        Only read (export, analyses): nothing is written, not even the WAL files when the directory is read-only.

    Raises
    ------
    StoreError
        If the file is absent (``readonly``), not writable (not ``readonly``), not an SQLite file, another
        application's database, a trial database of another layout, or damaged. Every later query raises it too
        (never a bare ``sqlite3.DatabaseError``), naming the file and what to do.

    Examples
    --------
    >>> import tempfile, os
    >>> with TrialStore(os.path.join(tempfile.mkdtemp(), "t.sqlite")) as s:
    ...     s.count()
    0
    """

    def __init__(self, path: str | Path, *, timeout_s: float = 60.0, readonly: bool = False):
        self.path = Path(path)
        self.timeout_s = float(timeout_s)
        self.readonly = bool(readonly)
        self.con: sqlite3.Connection | None = None
        self._robots: dict[str, str] = {}
        self._legacy: dict[str, None] = {}
        if self.readonly:
            self._open_readonly()
        else:
            self._open_writable()
        try:
            self._check_layout()
        except BaseException:
            self.close()
            raise

    # -- opening -------------------------------------------------------------------------------------------
    def _not_writable(self, why: str) -> StoreError:
        return StoreError(
            f"database '{self.path}' is not writable ({why}): a sweep appends to it; make it "
            f"writable (chmod u+w on the file and its directory) or give another --db"
        )

    def _open_writable(self) -> None:
        parent = self.path.parent
        if not parent.is_dir():
            raise StoreError(f"directory of database '{self.path}' does not exist; create it first")
        if self.path.exists() and not self.path.is_file():
            raise StoreError(f"database '{self.path}' is not a file; give the path of an SQLite file")
        if self.path.exists() and not os.access(self.path, os.W_OK):
            raise self._not_writable("read-only file")
        if not os.access(parent, os.W_OK | os.X_OK):
            raise self._not_writable(f"read-only directory '{parent}', where SQLite keeps its journal")
        try:
            self.con = sqlite3.connect(str(self.path), timeout=self.timeout_s, isolation_level=None)
        except sqlite3.Error as exc:
            raise self._error(exc, "opening it") from None

    def _open_readonly(self) -> None:
        if not self.path.is_file():
            raise StoreError(f"database '{self.path}' not found; run a sweep with --db {self.path} first")
        uri = self.path.resolve().as_uri()
        try:
            self.con = sqlite3.connect(
                f"{uri}?mode=ro", uri=True, timeout=self.timeout_s, isolation_level=None
            )
            self.con.execute("PRAGMA application_id").fetchone()
        except sqlite3.Error as exc:
            if self.con is not None:
                self.con.close()
                self.con = None
            if _sqlite_code(exc) not in ("SQLITE_READONLY_DIRECTORY", "SQLITE_CANTOPEN"):
                raise self._error(exc, "opening it") from None
            # a WAL database in a read-only directory: SQLite cannot make its shared-memory file. Unless a
            # write-ahead log holds rows not yet in the file, the file is read as immutable (nobody can write
            # there: the journal could not be made either)
            wal = Path(f"{self.path}-wal")
            if wal.is_file() and wal.stat().st_size > 0:
                raise StoreError(
                    f"'{self.path}' has trials still in its write-ahead log '{wal}' and its directory "
                    "is read-only, so they cannot be read; make the directory writable, or copy the "
                    "database with its -wal file to a writable directory"
                ) from None
            try:
                self.con = sqlite3.connect(f"{uri}?immutable=1", uri=True, isolation_level=None)
            except sqlite3.Error as exc2:
                raise self._error(exc2, "opening it") from None

    def _tables(self) -> list[str]:
        return [
            r[0]
            for r in self.con.execute(
                "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite%' ORDER BY name"
            )
        ]

    def _header(self) -> tuple[int, int, list[str]]:
        app = int(self.con.execute("PRAGMA application_id").fetchone()[0])
        ver = int(self.con.execute("PRAGMA user_version").fetchone()[0])
        return app, ver, self._tables()

    def _trials_layout(self) -> str:
        """'current' if the trials table is exactly this version's, else a reason it is not."""
        have = list(self.con.execute("PRAGMA table_info(trials)"))
        names = {r[1] for r in have}
        lacking = [c for c in COLUMNS if c not in names]
        if lacking:
            return f"no column {lacking[0]}"
        ref = sqlite3.connect(":memory:")
        try:
            ref.execute(SCHEMA)
            want = list(ref.execute("PRAGMA table_info(trials)"))
        finally:
            ref.close()
        if have != want:
            extra = sorted(names - set(COLUMNS))
            return f"extra column {extra[0]}" if extra else "other column types or key"
        return "current"

    def _check_layout(self) -> None:
        with self._guard("reading its header"):
            if not self.readonly:
                self.con.execute(f"PRAGMA busy_timeout = {int(self.timeout_s * 1000)}")
            app, ver, tables = self._header()
            if app == 0 and not tables and not self.readonly:
                self._create()
                app, ver, tables = self._header()
            if app == 0 and tables:
                self._adopt(tables)
                app, ver, tables = self._header()
            if app not in (0, APPLICATION_ID):
                raise StoreError(
                    f"'{self.path}' is another application's SQLite database (application_id "
                    f"{app:#x}), not a trial store; give a new --db file"
                )
            if app == 0 and not tables:  # readonly and empty
                raise StoreError(
                    f"'{self.path}' is an empty file, not a trial store; run a sweep with --db "
                    f"{self.path} first"
                )
            if ver > STORE_VERSION:
                raise StoreError(
                    f"'{self.path}' was written by a newer version (store layout {ver} > "
                    f"{STORE_VERSION}); use that version or a new --db"
                )
            if app == APPLICATION_ID and "trials" not in tables:
                raise StoreError(
                    f"'{self.path}' is a trial store without a trials table; it was damaged: "
                    "restore it from a backup or give a new --db"
                )
            layout = self._trials_layout()
            if self._lacks_only_late(layout):
                if self.readonly:  # read the missing columns as NULL, without writing
                    names = {r[1] for r in self.con.execute("PRAGMA table_info(trials)")}
                    self._legacy = {c: None for c in LATE_COLUMNS if c not in names}
                    layout = "current" if set(COLUMNS) - names <= set(self._legacy) else layout
                else:
                    self._add_late_columns()
                    layout = self._trials_layout()
            if layout.startswith("no column"):
                raise StoreError(
                    f"'{self.path}' was written by an older version ({layout}); export it with that "
                    "version or start a new database"
                )
            if not self.readonly:
                self.con.execute("PRAGMA journal_mode = WAL")
                self.con.execute("PRAGMA synchronous = NORMAL")
            self._robots = (
                dict(self.con.execute("SELECT robot, robot_hash FROM robots")) if "robots" in tables else {}
            )

    def _lacks_only_late(self, layout: str) -> bool:
        """Whether the trials table lacks columns and every one it lacks is one of :data:`LATE_COLUMNS`."""
        if not layout.startswith("no column"):
            return False
        names = {r[1] for r in self.con.execute("PRAGMA table_info(trials)")}
        return set(COLUMNS) - names <= set(LATE_COLUMNS)

    def _add_late_columns(self) -> None:
        """Give an older store the columns of :data:`LATE_COLUMNS` it lacks, in order: its trials get the
        ``paper`` set (the only model before sets existed), an unknown (NULL) side and the pybullet engine (the
        only one before engines existed)."""
        from .engine import DEFAULT_ENGINE
        from .model_set import load_model_set

        paper = load_model_set("paper")
        fill = {
            "model_set": paper.name,
            "model_set_hash": paper.model_set_hash,
            "side": None,
            "engine": DEFAULT_ENGINE,
        }
        self.con.execute("BEGIN IMMEDIATE")
        try:
            names = {r[1] for r in self.con.execute("PRAGMA table_info(trials)")}
            for col in LATE_COLUMNS:
                if col not in names:
                    self.con.execute(f"ALTER TABLE trials ADD COLUMN {col} {_TYPES[col]}")
                    if fill[col] is not None:
                        self.con.execute(f"UPDATE trials SET {col} = ?", (fill[col],))
            self.con.execute("COMMIT")
        except BaseException:
            self.con.execute("ROLLBACK")
            raise

    def _create(self) -> None:
        """Make the tables and the marker of a new store (in one transaction: another sweep may be creating it
        at the same moment)."""
        self.con.execute("BEGIN IMMEDIATE")
        try:
            app, _, tables = self._header()
            if app == 0 and not tables:
                self.con.execute(SCHEMA)
                self.con.execute(ROBOTS_SCHEMA)
                self.con.execute(f"PRAGMA application_id = {APPLICATION_ID}")
                self.con.execute(f"PRAGMA user_version = {STORE_VERSION}")
            self.con.execute("COMMIT")
        except BaseException:
            self.con.execute("ROLLBACK")
            raise

    def _adopt(self, tables: list[str]) -> None:
        """Accept a store made before the marker existed if it holds exactly this layout's trials table; mark it
        (unless read-only), registering each robot path with the hash of its latest trial. Refuse anything else."""
        if tables != ["trials"]:
            raise StoreError(
                f"'{self.path}' is an SQLite database of another application (tables: "
                f"{', '.join(tables)}), not a trial store; give a new --db file"
            )
        layout = self._trials_layout()
        if self._lacks_only_late(layout):
            if not self.readonly:
                self._add_late_columns()
                layout = self._trials_layout()
            else:
                names = {r[1] for r in self.con.execute("PRAGMA table_info(trials)")}
                self._legacy = {c: None for c in LATE_COLUMNS if c not in names}
                layout = "current"
        if layout.startswith("no column"):
            raise StoreError(
                f"'{self.path}' was written by an older version ({layout}); export it with that "
                "version or start a new database"
            )
        if layout != "current":
            raise StoreError(
                f"'{self.path}' has a trials table that is not a trial store's ({layout}): another "
                "application's database; give a new --db file"
            )
        if self.readonly:
            return
        self.con.execute("BEGIN IMMEDIATE")
        try:
            if self._header()[0] == 0:
                self.con.execute(ROBOTS_SCHEMA)
                self.con.execute(
                    "INSERT OR IGNORE INTO robots SELECT robot, robot_hash, MAX(created_utc) FROM trials "
                    "WHERE robot IS NOT NULL GROUP BY robot, robot_hash ORDER BY MAX(created_utc) DESC"
                )
                self.con.execute(f"PRAGMA application_id = {APPLICATION_ID}")
                self.con.execute(f"PRAGMA user_version = {STORE_VERSION}")
            self.con.execute("COMMIT")
        except BaseException:
            self.con.execute("ROLLBACK")
            raise

    # -- errors --------------------------------------------------------------------------------------------
    def _error(self, exc: sqlite3.Error, doing: str) -> StoreError:
        """The store's one-line error for an SQLite error met while ``doing``."""
        code = _sqlite_code(exc)
        if code == "SQLITE_NOTADB":
            return StoreError(
                f"'{self.path}' is not an SQLite database ({exc}); give the path of a trial store "
                "or a new --db file"
            )
        if code.startswith("SQLITE_CORRUPT"):
            return StoreError(_DAMAGED.format(path=self.path, what=f"{exc} while {doing}"))
        if code == "SQLITE_CANTOPEN" and self.readonly:
            return StoreError(f"'{self.path}' cannot be read ({exc}); check its permissions")
        if code.startswith("SQLITE_READONLY") or code == "SQLITE_CANTOPEN":
            return self._not_writable(str(exc))
        if code.startswith(("SQLITE_BUSY", "SQLITE_LOCKED")):
            return StoreError(
                f"'{self.path}' stayed locked by another process for {self.timeout_s:g} s while "
                f"{doing}; wait for it to finish or give another --db"
            )
        if code == "SQLITE_FULL":
            return StoreError(
                f"the disk of '{self.path}' is full while {doing}; free space and rerun (the "
                "trials stored so far are kept)"
            )
        return StoreError(f"'{self.path}' is not a usable SQLite trial database ({exc} while {doing})")

    @contextmanager
    def _guard(self, doing: str) -> Iterator[None]:
        try:
            yield
        except sqlite3.Error as exc:
            raise self._error(exc, doing) from None

    # -- use -----------------------------------------------------------------------------------------------
    def __enter__(self) -> TrialStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        if self.con is not None:
            self.con.close()
            self.con = None

    def done_keys(self) -> set[tuple]:
        """Key tuples (``KEY_COLUMNS`` order) of every stored trial."""
        with self._guard("reading the stored trial keys"):
            return set(self.con.execute(f"SELECT {', '.join(KEY_COLUMNS)} FROM trials"))

    def has(self, key: Sequence) -> bool:
        """Whether the trial with this key (``KEY_COLUMNS`` order) is stored."""
        with self._guard("looking up a trial"):
            return (
                self.con.execute(
                    f"SELECT 1 FROM trials WHERE {' AND '.join(f'{c} = ?' for c in KEY_COLUMNS)} LIMIT 1",
                    tuple(key),
                ).fetchone()
                is not None
            )

    def check_robot(self, robot: str, robot_hash: str) -> None:
        """Register the description hash of a robot file, or refuse a file that changed since its trials here
        were run.

        Raises
        ------
        RobotChangedError
            If this database's trials of the robot file ``robot`` were run with another description hash.
        """
        robot = str(robot)
        if robot not in self._robots:
            with self._guard("registering the robot"):
                if not self.readonly:
                    self.con.execute(
                        "INSERT OR IGNORE INTO robots VALUES (?, ?, ?)", (robot, robot_hash, _now_utc())
                    )
                got = self.con.execute("SELECT robot_hash FROM robots WHERE robot = ?", (robot,)).fetchone()
            if got is None:  # read-only store: nothing to compare with
                return
            self._robots[robot] = got[0]
        if self._robots[robot] != robot_hash:
            raise RobotChangedError(
                f"robot file '{robot}' changed: '{self.path}' was swept with it at description hash "
                f"{self._robots[robot]}, the file now hashes to {robot_hash}; mixing them would pool two robots. "
                "Sweep the changed robot into a new --db, or restore the robot file"
            )

    def check_engine(self, engine: str) -> None:
        """Refuse to add trials of another engine than the one this store's trials were run in.

        Raises
        ------
        StoreError
            If a stored trial ran in another engine (a NULL engine is pybullet's).
        """
        from .engine import DEFAULT_ENGINE

        with self._guard("reading the engines"):
            other = self.con.execute(
                "SELECT COALESCE(engine, ?) AS e FROM trials WHERE e IS NOT ? LIMIT 1",
                (DEFAULT_ENGINE, engine),
            ).fetchone()
        if other is not None:
            raise StoreError(
                f"'{self.path}' holds {other[0]} trials, not {engine} ones; mixing engines would pool two models. "
                f"Sweep into another --db, or pass --engine {other[0]}"
            )

    def check_model_set(self, name: str, model_set_hash: str) -> None:
        """Refuse to add trials of a model set other than the one this store's trials were run with.

        Raises
        ------
        StoreError
            If a stored trial has another model set hash.
        """
        with self._guard("reading the model sets"):
            other = self.con.execute(
                "SELECT model_set, model_set_hash FROM trials WHERE model_set_hash IS NOT ? LIMIT 1",
                (model_set_hash,),
            ).fetchone()
        if other is not None:
            raise StoreError(
                f"'{self.path}' holds trials of model set {other[0]} (hash {other[1]}), not {name} (hash "
                f"{model_set_hash}); mixing them would pool two models. Sweep into a new --db, or pass "
                f"--model {other[0]}"
            )

    def add(self, row: dict) -> bool:
        """Store one trial (committed at once); False if it was already there.

        Raises
        ------
        RobotChangedError
            If the row's robot file was swept into this database with another description hash.
        """
        if row.get("robot") is not None:
            self.check_robot(row["robot"], row["robot_hash"])
        vals = [
            json.dumps(row.get(c)) if c in ("phases", "attempt_starts_s") else row.get(c) for c in COLUMNS
        ]
        with self._guard("storing a trial"):
            cur = self.con.execute(
                f"INSERT OR IGNORE INTO trials ({', '.join(COLUMNS)}) VALUES ({', '.join('?' * len(COLUMNS))})",
                vals,
            )
        return cur.rowcount == 1

    def count(self) -> int:
        with self._guard("counting the trials"):
            return int(self.con.execute("SELECT COUNT(*) FROM trials").fetchone()[0])

    def rows(self) -> list[dict]:
        """Every trial as a dict, in key order."""
        out = []
        with self._guard("reading the trials"):
            cols = [f"NULL AS {c}" if c in self._legacy else c for c in COLUMNS]
            cur = self.con.execute(f"SELECT {', '.join(cols)} FROM trials ORDER BY {', '.join(KEY_COLUMNS)}")
            for r in cur:
                d = dict(zip(COLUMNS, r, strict=True))
                for c in ("phases", "attempt_starts_s"):
                    d[c] = json.loads(d[c]) if d[c] else []
                d["success"] = None if d["success"] is None else bool(d["success"])
                out.append(d)
        return out

    def robots(self) -> dict[str, str]:
        """Robot file -> the description hash it was swept with."""
        with self._guard("reading the robots"):
            if "robots" not in self._tables():
                return {}
            return dict(self.con.execute("SELECT robot, robot_hash FROM robots ORDER BY robot"))

    def integrity_ok(self) -> bool:
        with self._guard("checking its integrity"):
            return self.con.execute("PRAGMA integrity_check").fetchone()[0] == "ok"


def read_rows(db: str | Path) -> list[dict]:
    """Every trial of an existing database, read without writing to it (export, analyses).

    Raises
    ------
    StoreError
        If ``db`` does not exist, is not a trial database, or is damaged.
    """
    with TrialStore(db, readonly=True) as store:
        return store.rows()


def export_csv(db: str | Path, csv_path: str | Path) -> int:
    """Write every trial of a database to CSV (phases as ';'-joined values); return the row count.

    Raises
    ------
    StoreError
        If ``db`` does not exist or is not a trial database.
    """
    rows = read_rows(db)
    csv_path = Path(csv_path)
    csv_path.parent.mkdir(parents=True, exist_ok=True)
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        for d in rows:
            w.writerow(
                [
                    ";".join(f"{x:.6g}" for x in d[c])
                    if c in ("phases", "attempt_starts_s")
                    else ("" if d[c] is None else int(d[c]) if c == "success" else d[c])
                    for c in COLUMNS
                ]
            )
    return len(rows)
