"""SQLite store of trial results: one row per trial, keyed by every parameter and the seed.

The database runs in WAL mode with a 60 s busy timeout, so several sweeps (processes) can append to one file at
once; each result is committed on its own as it arrives (``INSERT OR IGNORE``: a trial that another sweep
already stored is kept as it was), so killing a sweep loses at most the trials still running.
"""

from __future__ import annotations

import csv
import json
import sqlite3
from pathlib import Path

from geometry.errors import UsageError

KEY_COLUMNS = ("robot_hash", "theta_w_deg", "theta_l_deg", "cv", "phase", "trial", "duration_s", "dt_s",
               "wing_period_s", "leg_period_s", "attempts", "seed")
"""Every parameter of a trial; ``attempts`` 0 means "as many as fit in ``duration_s``"."""
COLUMNS = KEY_COLUMNS + (
    "status", "success", "time_to_right_s", "attempt", "mode", "phases", "attempt_starts_s", "sim_s", "wall_s",
    "cpu_s", "max_tracking_error_deg", "model_hash", "robot", "version", "error", "created_utc",
)
_TYPES = {"robot_hash": "TEXT NOT NULL", "theta_w_deg": "REAL NOT NULL", "theta_l_deg": "REAL NOT NULL",
          "cv": "REAL NOT NULL", "phase": "REAL NOT NULL", "trial": "INTEGER NOT NULL",
          "duration_s": "REAL NOT NULL", "dt_s": "REAL NOT NULL", "wing_period_s": "REAL NOT NULL",
          "leg_period_s": "REAL NOT NULL", "attempts": "INTEGER NOT NULL", "seed": "INTEGER NOT NULL",
          "status": "TEXT NOT NULL", "success": "INTEGER", "time_to_right_s": "REAL", "attempt": "INTEGER",
          "mode": "TEXT", "phases": "TEXT", "attempt_starts_s": "TEXT", "sim_s": "REAL", "wall_s": "REAL",
          "cpu_s": "REAL", "max_tracking_error_deg": "REAL", "model_hash": "TEXT", "robot": "TEXT",
          "version": "TEXT", "error": "TEXT", "created_utc": "TEXT"}
SCHEMA = (
    "CREATE TABLE IF NOT EXISTS trials ("
    + ", ".join(f"{c} {_TYPES[c]}" for c in COLUMNS)
    + f", PRIMARY KEY ({', '.join(KEY_COLUMNS)}))"
)


class StoreError(UsageError):
    """The file is not a trial database of this layout."""


class TrialStore:
    """A trial database; use as a context manager.

    Examples
    --------
    >>> import tempfile, os
    >>> with TrialStore(os.path.join(tempfile.mkdtemp(), "t.sqlite")) as s:
    ...     s.count()
    0
    """

    def __init__(self, path: str | Path, *, timeout_s: float = 60.0):
        self.path = Path(path)
        if self.path.parent and not self.path.parent.exists():
            raise StoreError(f"directory of database '{self.path}' does not exist; create it first")
        try:
            self.con = sqlite3.connect(str(self.path), timeout=timeout_s, isolation_level=None)
            self.con.execute(f"PRAGMA busy_timeout = {int(timeout_s * 1000)}")
            self.con.execute("PRAGMA journal_mode = WAL")
            self.con.execute("PRAGMA synchronous = NORMAL")
            self.con.execute(SCHEMA)
            have = {r[1] for r in self.con.execute("PRAGMA table_info(trials)")}
        except sqlite3.DatabaseError as exc:
            raise StoreError(f"'{self.path}' is not a usable SQLite trial database: {exc}") from None
        lacking = [c for c in COLUMNS if c not in have]
        if lacking:
            self.con.close()
            raise StoreError(f"'{self.path}' was written by an older version (no column {lacking[0]}); export it "
                             "with that version or start a new database")

    def __enter__(self) -> TrialStore:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        self.con.close()

    def done_keys(self) -> set[tuple]:
        """Key tuples (``KEY_COLUMNS`` order) of every stored trial."""
        return set(self.con.execute(f"SELECT {', '.join(KEY_COLUMNS)} FROM trials"))

    def add(self, row: dict) -> bool:
        """Store one trial (committed at once); False if it was already there."""
        vals = [json.dumps(row.get(c)) if c in ("phases", "attempt_starts_s") else row.get(c) for c in COLUMNS]
        cur = self.con.execute(
            f"INSERT OR IGNORE INTO trials ({', '.join(COLUMNS)}) VALUES ({', '.join('?' * len(COLUMNS))})", vals)
        return cur.rowcount == 1

    def count(self) -> int:
        return int(self.con.execute("SELECT COUNT(*) FROM trials").fetchone()[0])

    def rows(self) -> list[dict]:
        """Every trial as a dict, in key order."""
        cur = self.con.execute(f"SELECT {', '.join(COLUMNS)} FROM trials ORDER BY {', '.join(KEY_COLUMNS)}")
        out = []
        for r in cur:
            d = dict(zip(COLUMNS, r, strict=True))
            for c in ("phases", "attempt_starts_s"):
                d[c] = json.loads(d[c]) if d[c] else []
            d["success"] = None if d["success"] is None else bool(d["success"])
            out.append(d)
        return out

    def integrity_ok(self) -> bool:
        return self.con.execute("PRAGMA integrity_check").fetchone()[0] == "ok"


def export_csv(db: str | Path, csv_path: str | Path) -> int:
    """Write every trial of a database to CSV (phases as ';'-joined values); return the row count.

    Raises
    ------
    StoreError
        If ``db`` does not exist or is not a trial database.
    """
    db = Path(db)
    if not db.is_file():
        raise StoreError(f"database '{db}' not found; run a sweep with --db {db} first")
    with TrialStore(db) as store:
        rows = store.rows()
    csv_path = Path(csv_path)
    csv_path.parent.mkdir(parents=True, exist_ok=True)
    with open(csv_path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        for d in rows:
            w.writerow([";".join(f"{x:.6g}" for x in d[c]) if c in ("phases", "attempt_starts_s")
                        else ("" if d[c] is None else int(d[c]) if c == "success" else d[c]) for c in COLUMNS])
    return len(rows)
