"""A processor's own Python environment, for Python FMUs (pythonfmu) that import packages the
server does not have.

A processor with `python_requirements` runs its worker in a virtualenv made from that list,
under data_dir/fmu-envs/<hash>/, where the hash is of the sorted requirements and the server's
Python version: processors that ask for the same list share one env, built once. A `.pth` file
in the env's site-packages adds the server's site-packages AFTER the env's own (with
`site.addsitedir`, so the server's own `.pth` files, twinlink's editable install among them,
are read too): the worker finds twinlink, FMPy and numpy there, and a package the env has
wins over the server's copy of it. A finished build is marked by a `ready` file written last,
so an env half built when the server stopped is built again, never used.
"""

from __future__ import annotations

import asyncio
import contextlib
import fcntl
import hashlib
import json
import logging
import os
import shutil
import site
import sys
import sysconfig
import time
from collections.abc import AsyncIterator, Callable
from pathlib import Path

log = logging.getLogger("twinlink.processors")

READY = "ready"
LOCK_POLL_S = 0.5
RETRY_AFTER_S = 60.0  # a failed build fails again at once until then (no pip storm)
REQUIREMENTS_FILE = "requirements.txt"  # beside an FMU in a library model asset
PIP_TAIL_LINES = 20
# What of the server's environment pip sees: where to find packages (a mirror, its
# certificates, a proxy) and nothing else, so no TWINLINK_* setting or other secret reaches it.
PIP_PASSED = ("PATH", "HOME", "LANG", "LC_ALL", "TMPDIR", "SSL_CERT_FILE", "SSL_CERT_DIR")
PIP_PASSED_PREFIXES = ("PIP_INDEX_URL", "PIP_EXTRA_INDEX_URL", "PIP_TRUSTED_HOST", "PIP_CERT",
                       "PIP_FIND_LINKS", "PIP_NO_INDEX", "PIP_TIMEOUT", "PIP_RETRIES")  # fmt: skip
PROXIES = ("HTTP_PROXY", "HTTPS_PROXY", "NO_PROXY", "http_proxy", "https_proxy", "no_proxy")


class EnvBuildError(Exception):
    """The env could not be built; the message ends with pip's last lines. Not a problem of
    the API's: the supervisor catches it and fails the processor with its message."""


def requirement_problem(line: str) -> str | None:
    """Why `line` is not one requirement (None: it is). One package each: pip options
    (`-r`, `--index-url`, `--hash`) could point pip at any file or index."""
    option = line.lstrip().startswith("-") or " -" in line or "\n" in line
    if option or not line.strip() or len(line) > 300:
        return (
            f"{line!r} is not a requirement: give one package each, as `name==version` "
            "(pip options and files are not allowed)"
        )
    return None


def parse_requirements(text: str, where: str) -> list[str]:
    """The requirements of a requirements.txt (comments and blank lines left out); ValueError
    naming the line that is not one."""
    found = []
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.split(" #", 1)[0].strip()
        if not line or line.startswith("#"):
            continue
        if (problem := requirement_problem(line)) is not None:
            raise ValueError(f"{where} line {number}: {problem}")
        found.append(line)
    return found


def env_key(requirements: list[str]) -> str:
    """The env's folder name: the same requirements (in any order) on the same Python share it."""
    python = f"{sys.implementation.name}-{sys.version_info.major}.{sys.version_info.minor}"
    text = json.dumps({"python": python, "requirements": sorted(set(requirements))})
    return hashlib.sha256(text.encode()).hexdigest()[:24]


def pip_environment() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k in PIP_PASSED or k in PROXIES}
    env.update({k: v for k, v in os.environ.items() if k.startswith(PIP_PASSED_PREFIXES)})
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    env["PYTHONNOUSERSITE"] = "1"
    return env


def server_site_dirs() -> list[str]:
    """The server's site-packages folders, its own before its base Python's."""
    dirs = [sysconfig.get_path("purelib"), sysconfig.get_path("platlib"), *site.getsitepackages()]
    return list(dict.fromkeys(d for d in dirs if Path(d).is_dir()))


class FmuEnvs:
    """The per-requirements envs under `root` (data_dir/fmu-envs): found, or built once."""

    def __init__(self, root: Path, build_timeout_s: float = 900.0) -> None:
        self.root = root
        self.build_timeout_s = build_timeout_s
        self._locks: dict[str, asyncio.Lock] = {}
        self._failed: dict[str, tuple[str, float]] = {}  # key -> why its build failed, when

    def python_of(self, requirements: list[str]) -> Path:
        return self.root / env_key(requirements) / "bin" / "python"

    def is_ready(self, requirements: list[str]) -> bool:
        return (self.root / env_key(requirements) / READY).is_file()

    async def python(
        self, requirements: list[str], building: Callable[[str], None] | None = None
    ) -> Path:
        """The interpreter of the env for `requirements`, built first if need be (`building`
        is told the key when a build starts). Concurrent callers for one env wait for one
        build; a build that failed fails again at once, with the same message, for
        RETRY_AFTER_S (the processors that waited for it, a restart right after)."""
        key = env_key(requirements)
        lock = self._locks.setdefault(key, asyncio.Lock())
        async with lock:
            failed = self._failed.pop(key, None)
            if failed is not None and time.monotonic() - failed[1] < RETRY_AFTER_S:
                self._failed[key] = failed
                raise EnvBuildError(failed[0])
            folder = self.root / key
            if not (folder / READY).is_file():
                if building is not None:
                    building(key)
                async with _file_lock(self.root / f"{key}.lock"):  # other server processes
                    if not (folder / READY).is_file():
                        try:
                            await self._build(folder, requirements)
                        except EnvBuildError as err:
                            self._failed[key] = (str(err), time.monotonic())
                            raise
            return folder / "bin" / "python"

    async def _build(self, folder: Path, requirements: list[str]) -> None:
        await asyncio.to_thread(shutil.rmtree, folder, True)  # a build cut short before
        folder.parent.mkdir(parents=True, exist_ok=True)
        log.info("building the Python env %s for %s", folder.name, requirements)
        # Without pip of its own: the server's pip installs into it (`pip --python`), which
        # saves the env a copy of pip and works where ensurepip is missing.
        await _run([sys.executable, "-m", "venv", "--without-pip", str(folder)], "venv")
        python = folder / "bin" / "python"
        purelib = "import sysconfig; print(sysconfig.get_path('purelib'))"
        env_site = await _output([str(python), "-c", purelib])
        lines = [f"import site; site.addsitedir({d!r})" for d in server_site_dirs()]
        (Path(env_site) / "_twinlink_server.pth").write_text("\n".join(lines) + "\n")
        (folder / "requirements.txt").write_text("\n".join(requirements) + "\n")
        # --ignore-installed: the server's packages are visible through the .pth file, and
        # pip must not count them as already installed.
        await _run(
            [sys.executable, "-m", "pip", "--python", str(python), "install", "--no-input",
             "--ignore-installed", "-r", str(folder / "requirements.txt")],
            "pip install",
            self.build_timeout_s,
        )  # fmt: skip
        (folder / READY).write_text(json.dumps({"requirements": requirements}) + "\n")


@contextlib.asynccontextmanager
async def _file_lock(path: Path) -> AsyncIterator[None]:
    """An exclusive lock on `path` across processes (`--workers N`, nodes on one data dir),
    polled so that waiting for it can be cancelled."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("a") as file:
        while True:
            try:
                fcntl.flock(file, fcntl.LOCK_EX | fcntl.LOCK_NB)
                break
            except BlockingIOError:
                await asyncio.sleep(LOCK_POLL_S)
        try:
            yield
        finally:
            fcntl.flock(file, fcntl.LOCK_UN)


async def _run(command: list[str], what: str, timeout_s: float | None = None) -> None:
    proc = await asyncio.create_subprocess_exec(
        *command, stdin=asyncio.subprocess.DEVNULL, stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.STDOUT, env=pip_environment(),
    )  # fmt: skip
    try:
        out, _ = await asyncio.wait_for(proc.communicate(), timeout_s)
    except (asyncio.CancelledError, TimeoutError) as err:  # no pip left behind
        with contextlib.suppress(ProcessLookupError):
            proc.kill()
        await proc.wait()
        if isinstance(err, TimeoutError):
            raise EnvBuildError(
                f"{what} took longer than {timeout_s:g} s (TWINLINK_FMU_ENV_BUILD_TIMEOUT_S)"
            ) from err
        raise
    if proc.returncode != 0:
        tail = out.decode("utf-8", "replace").strip().splitlines()[-PIP_TAIL_LINES:]
        raise EnvBuildError(f"{what} failed (exit status {proc.returncode}):\n" + "\n".join(tail))


async def _output(command: list[str]) -> str:
    proc = await asyncio.create_subprocess_exec(
        *command, stdin=asyncio.subprocess.DEVNULL, stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.STDOUT, env=pip_environment(),
    )  # fmt: skip
    out, _ = await proc.communicate()
    text = out.decode("utf-8", "replace").strip()
    if proc.returncode != 0:
        raise EnvBuildError(f"the new env's Python does not run: {text[-2000:]}")
    return text
