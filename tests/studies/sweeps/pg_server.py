"""A throwaway PostgreSQL server on 127.0.0.1 for the distributed-sweep tests and the race
measurements (bench/storage_races.py): initdb, pg_ctl start on a free port, one database, stop.

The binaries are Debian's (``apt-get install postgresql``: /usr/lib/postgresql/VERSION/bin), any
``initdb`` on PATH, or those in ``$SOFTCRAWL_PG_BIN``. PostgreSQL refuses to run as root; as root
the server runs as the ``postgres`` user of the Debian package, in a folder of its own under the
system's temporary directory (pytest's tmp_path is private to root), removed afterwards.
Authentication: password (scram-sha-256) over TCP, so that a wrong password can be tested.
"""

from __future__ import annotations

import contextlib
import glob
import os
import pwd
import shutil
import socket
import subprocess
import tempfile
from collections.abc import Iterator
from pathlib import Path

USER, PASSWORD, DATABASE = "softcrawl", "sweep-test", "sweeps"


def find_binaries() -> Path | None:
    """The folder holding initdb and pg_ctl, or None."""
    candidates = [os.environ.get("SOFTCRAWL_PG_BIN", "")]
    debian = glob.glob("/usr/lib/postgresql/*/bin")
    candidates += sorted(debian, key=lambda p: int(p.split("/")[-2]), reverse=True)
    which = shutil.which("initdb")
    candidates.append(str(Path(which).resolve().parent) if which else "")
    for folder in candidates:
        if folder and (Path(folder) / "initdb").exists() and (Path(folder) / "pg_ctl").exists():
            return Path(folder)
    return None


def why_unavailable() -> str | None:
    """None if a server can be started here, else the reason (for pytest.skip)."""
    if find_binaries() is None:
        return "no PostgreSQL binaries (initdb, pg_ctl): apt-get install postgresql, or set SOFTCRAWL_PG_BIN"
    try:
        import psycopg  # noqa: F401
    except ImportError:
        return 'no PostgreSQL driver: pip install -e ".[postgres]"'
    if os.geteuid() == 0:
        try:
            pwd.getpwnam("postgres")
        except KeyError:
            return "running as root and no 'postgres' user to run the server as"
    return None


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@contextlib.contextmanager
def temporary_server(base: Path) -> Iterator[str]:
    """Start a server, yield the URL of an empty database, stop and remove it."""
    binaries = find_binaries()
    assert binaries is not None, why_unavailable()
    as_root = os.geteuid() == 0
    home = Path(tempfile.mkdtemp(prefix="softcrawl-pg-")) if as_root else Path(base) / "pg"
    home.mkdir(exist_ok=True)
    kwargs = {}
    if as_root:
        entry = pwd.getpwnam("postgres")
        os.chown(home, entry.pw_uid, entry.pw_gid)
        kwargs = {"user": entry.pw_uid, "group": entry.pw_gid}
    data, port = home / "data", _free_port()
    (home / "pw").write_text(PASSWORD + "\n")
    if as_root:
        os.chown(home / "pw", kwargs["user"], kwargs["group"])

    def run(*args: str) -> None:
        subprocess.run(args, check=True, capture_output=True, cwd=home, **kwargs)

    try:
        run(str(binaries / "initdb"), "-D", str(data), "-U", USER, f"--pwfile={home / 'pw'}",
            "--auth-host=scram-sha-256", "--auth-local=trust", "-E", "UTF8", "--no-sync")  # fmt: skip
        options = f"-c listen_addresses=127.0.0.1 -p {port} -k {home} -c fsync=off -c max_connections=50"
        log = str(home / "log")
        run(str(binaries / "pg_ctl"), "-D", str(data), "-o", options, "-l", log, "-w", "-t", "60", "start")
        try:
            import psycopg

            with psycopg.connect(
                host="127.0.0.1", port=port, user=USER, password=PASSWORD, dbname="postgres", autocommit=True
            ) as con:
                con.execute(f"CREATE DATABASE {DATABASE}")
            yield f"postgresql://{USER}:{PASSWORD}@127.0.0.1:{port}/{DATABASE}"
        finally:
            run(str(binaries / "pg_ctl"), "-D", str(data), "-m", "immediate", "-w", "stop")
    finally:
        if as_root:
            shutil.rmtree(home, ignore_errors=True)
