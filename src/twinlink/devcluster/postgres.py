"""A PostgreSQL server of Debian's `postgresql` package, started from its programs (no
system service): for the local cluster (its data kept across starts) and the tests (a
throwaway cluster, fsync off).

initdb and postgres refuse to run as root: run as root, the cluster's folder belongs to the
`postgres` user the package creates and the server runs as that user; run as anyone else,
as that user. The server is a child of the process that started it and dies with it.
Administration (roles, databases) goes through the package's `psql` on the server's own Unix
socket, in a folder only the cluster's owner can enter: no driver is imported here.
"""

from __future__ import annotations

import os
import pwd
import shutil
import signal
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

from twinlink.devcluster._process import dying_with_parent, free_ports, stop_process
from twinlink.domain.errors import TwinlinkError

START_S = 60.0  # a cold initdb and start on a busy 2-core machine take a few seconds
STOP_S = 30.0
SUPERUSER = "postgres"


class PostgresError(TwinlinkError):
    """PostgreSQL is missing, or its server did not start or refused a command."""


@dataclass
class PostgresServer:
    bin_dir: Path
    folder: Path  # data/, sockets/ and postgres.log
    port: int
    process: subprocess.Popen[bytes]

    def log(self, tail: int = 3000) -> str:
        try:
            return (self.folder / "postgres.log").read_text(errors="replace")[-tail:]
        except OSError:
            return ""

    def psql(self, sql: str, database: str = "postgres") -> str:
        """Run `sql` as the superuser over the Unix socket; its output, or PostgresError. The
        SQL goes in on standard input: a password in it never shows in the process list."""
        done = subprocess.run(
            [self.bin_dir / "psql", "-X", "-q", "-t", "-A", "-v", "ON_ERROR_STOP=1",
             "-h", self.folder / "sockets", "-p", str(self.port), "-U", SUPERUSER,
             "-d", database, "-f", "-"],
            input=sql, capture_output=True, text=True, check=False,
            **run_as(),  # type: ignore[call-overload]
        )  # fmt: skip
        if done.returncode != 0:
            raise PostgresError(f"psql failed: {done.stderr.strip()}")
        return str(done.stdout)

    def stop(self) -> None:
        stop_postgres(self.process)


def postgres_bin() -> Path:
    """The folder of the newest installed PostgreSQL's programs (Debian keeps them out of
    PATH, in /usr/lib/postgresql/VERSION/bin)."""
    versions = sorted(
        Path("/usr/lib/postgresql").glob("*/bin/postgres"),
        key=lambda p: int(p.parent.parent.name) if p.parent.parent.name.isdigit() else 0,
    )
    if versions:
        return versions[-1].parent
    found = shutil.which("postgres")
    if found is None:
        raise PostgresError(
            "PostgreSQL not found: install the Debian package postgresql "
            "(scripts/ensure-packages.sh postgresql, which make test and make cluster run)"
        )
    return Path(found).parent


def run_as() -> dict[str, object]:
    """Popen's arguments that run a program as the cluster's owner: `postgres` when we are
    root, ourselves otherwise."""
    if os.geteuid() != 0:
        return {}
    owner = pwd.getpwnam(SUPERUSER)
    return {"user": owner.pw_uid, "group": owner.pw_gid, "extra_groups": []}


def ready(bin_dir: Path, port: int) -> bool:
    done = subprocess.run(
        [bin_dir / "pg_isready", "-q", "-h", "127.0.0.1", "-p", str(port)], check=False
    )
    return done.returncode == 0


def initdb(bin_dir: Path, folder: Path, *, throwaway: bool) -> None:
    """Create the cluster in folder/data unless it is there already (a restart keeps it).
    A throwaway cluster trusts every loopback connection; a kept one trusts only its Unix
    socket (reachable by its owner alone) and asks for passwords over TCP."""
    sockets = folder / "sockets"
    sockets.mkdir(mode=0o700, parents=True, exist_ok=True)
    if os.geteuid() == 0:
        owner = pwd.getpwnam(SUPERUSER)
        for path in (folder, sockets):
            os.chown(path, owner.pw_uid, owner.pw_gid)
    if (folder / "data" / "PG_VERSION").exists():
        return
    auth = ["--auth=trust"] if throwaway else ["--auth-local=trust", "--auth-host=scram-sha-256"]
    done = subprocess.run(
        [bin_dir / "initdb", "-D", folder / "data", "-U", SUPERUSER, *auth, "-E", "UTF8",
         "--locale=C.UTF-8", *(["--no-sync"] if throwaway else [])],
        check=False, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, **run_as(),  # type: ignore[call-overload]
    )  # fmt: skip
    if done.returncode != 0:
        raise PostgresError(f"initdb failed in {folder}: {done.stderr.decode(errors='replace')}")


def launch(bin_dir: Path, folder: Path, port: int, *, throwaway: bool) -> subprocess.Popen[bytes]:
    """Start the server of folder/data on 127.0.0.1:port without waiting for it."""
    # a throwaway cluster trades durability for speed: a crash of the machine loses it
    fast = ["-c", "fsync=off", "-c", "full_page_writes=off", "-c", "synchronous_commit=off"]
    with (folder / "postgres.log").open("ab") as log:
        server: subprocess.Popen[bytes] = subprocess.Popen(
            [bin_dir / "postgres", "-D", folder / "data", "-p", str(port),
             "-k", folder / "sockets", "-c", "listen_addresses=127.0.0.1",
             "-c", "max_connections=200", *(fast if throwaway else [])],
            stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
            # SIGQUIT is PostgreSQL's "immediate shutdown"; set in the child after it became
            # the cluster's owner (which would clear the setting)
            preexec_fn=dying_with_parent(signal.SIGQUIT),
            process_group=0,  # a Ctrl-C in the terminal reaches the launcher alone
            **run_as(),  # type: ignore[call-overload]
        )  # fmt: skip
    return server


def start_postgres(
    folder: Path, port: int = 0, *, throwaway: bool = False, bin_dir: Path | None = None
) -> PostgresServer:
    """initdb (unless done) and start the server on 127.0.0.1:`port` (0: a free one); returns
    once it accepts connections."""
    bin_dir = bin_dir or postgres_bin()
    initdb(bin_dir, folder, throwaway=throwaway)
    for _attempt in range(3):
        chosen = port or free_ports(1)[0]
        server = PostgresServer(
            bin_dir, folder, chosen, launch(bin_dir, folder, chosen, throwaway=throwaway)
        )
        deadline = time.monotonic() + START_S
        while not ready(bin_dir, chosen):
            if server.process.poll() is not None or time.monotonic() > deadline:
                break
            time.sleep(0.05)  # polling the server's real state, with a deadline
        else:
            return server
        server.stop()
        # a port picked free was taken before the server bound it: pick another
        if port == 0 and "could not bind" in server.log():
            continue
        break
    raise PostgresError(f"PostgreSQL did not start on port {chosen}:\n{server.log()}")


def stop_postgres(process: subprocess.Popen[bytes]) -> None:
    """SIGINT, PostgreSQL's "fast" shutdown (ends the sessions, no waiting for them), then
    SIGKILL if it takes too long."""
    stop_process(process, signal.SIGINT, STOP_S)
