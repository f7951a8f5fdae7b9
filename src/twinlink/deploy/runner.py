"""One lifecycle run's process: started in a session of its own, limited, waited for, and
killed with everything it started.

The script's stdout and stderr go straight to the run's log file (the file is the child's
stdout), so the log is written as it comes and the server holds none of it in memory. The
process group is the session's: a timeout, a cancel or the run's end kills the whole group,
so a script's background children never outlive its run.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import resource
import shutil
import signal
import stat
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

# A cancelled run gets SIGTERM, then SIGKILL after this long: time for a script to save.
CANCEL_GRACE_S = 5.0
_SHEBANG_MAX = 256  # bytes of a script's first line read for its interpreter


@dataclass(frozen=True, slots=True)
class Limits:
    timeout_s: int = 0  # wall clock, 0: none
    memory_mb: int = 0  # address space (RLIMIT_AS), 0: none


@dataclass(frozen=True, slots=True)
class Outcome:
    state: Literal["succeeded", "failed", "cancelled"]
    exit_code: int | None  # negative: killed by that signal (as Python's returncode)
    error: str | None


def command_of(script: Path) -> list[str]:
    """How to run a phase script. DTaaS scripts often lack the executable bit, so the mode is
    not trusted: a script with a `#!` line runs with that interpreter, a binary runs as
    itself, anything else with /bin/sh."""
    with script.open("rb") as file:
        head = file.read(_SHEBANG_MAX)
    if head.startswith(b"#!"):
        line = head[2:].split(b"\n", 1)[0].decode("utf-8", "replace").strip()
        # As the kernel does: the interpreter, then everything after it as one argument.
        return [*line.split(None, 1), str(script)] if line else ["/bin/sh", str(script)]
    if head.startswith(b"\x7fELF"):
        return [str(script)]
    return ["/bin/sh", str(script)]


def own_files(work: Path) -> int:
    """Make every file under `work` the run's own: a hard link (the library materializes
    versions as links to its blobs) becomes a copy, so a script that makes a file writable and
    changes it changes its copy, not the library's content-addressed blob. The files copied."""
    copied = 0
    for folder, _, names in os.walk(work):
        for name in names:
            path = Path(folder) / name
            info = path.lstat()
            if not stat.S_ISREG(info.st_mode) or info.st_nlink < 2:
                continue
            temp = path.with_name(f".{name}.own")
            shutil.copyfile(path, temp)
            os.chmod(temp, stat.S_IMODE(info.st_mode))
            os.replace(temp, path)
            copied += 1
    return copied


def _limits_in_child(memory_mb: int) -> Callable[[], None]:
    def apply() -> None:  # runs in the child between fork and exec: nothing but syscalls
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if memory_mb:
            limit = memory_mb * 2**20
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    return apply


async def run_script(
    script: Path,
    work: Path,
    env: dict[str, str],
    log_path: Path,
    limits: Limits,
    on_started: Callable[[int], Awaitable[bool]],
) -> Outcome:
    """Run `script` in `work` until it ends, times out or this task is cancelled (the process
    group is then stopped, and CancelledError raised). `on_started(pid)` records the start;
    False (the run was cancelled meanwhile) stops the process at once."""
    try:
        command = command_of(script)
    except OSError as err:
        return Outcome("failed", None, f"could not read {script.name}: {err.strerror}")
    log_fd = os.open(log_path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o600)
    try:
        proc = await asyncio.create_subprocess_exec(
            *command, cwd=work, env=env, stdin=asyncio.subprocess.DEVNULL,
            stdout=log_fd, stderr=log_fd, start_new_session=True,
            preexec_fn=_limits_in_child(limits.memory_mb),
        )  # fmt: skip
    except OSError as err:
        return Outcome("failed", None, f"could not start {command[0]}: {err.strerror}")
    finally:
        os.close(log_fd)
    try:
        if not await on_started(proc.pid):
            await _stop(proc, 0)
            return Outcome("cancelled", proc.returncode, "cancelled before it started")
        return await _wait(proc, limits.timeout_s)
    except BaseException:
        await asyncio.shield(_stop(proc, CANCEL_GRACE_S))
        raise
    finally:
        _kill_group(proc.pid)  # what the script left running in the background


async def _wait(proc: asyncio.subprocess.Process, timeout_s: int) -> Outcome:
    try:
        await asyncio.wait_for(proc.wait(), timeout_s or None)
    except TimeoutError:
        await _stop(proc, 0)
        return Outcome("failed", proc.returncode, f"timed out after {timeout_s} s")
    code = proc.returncode
    assert code is not None
    if code == 0:
        return Outcome("succeeded", 0, None)
    if code < 0:
        return Outcome("failed", code, f"killed by signal {_signal_name(-code)}")
    return Outcome("failed", code, f"exited with code {code}")


async def _stop(proc: asyncio.subprocess.Process, grace_s: float) -> None:
    """Stop the process group: SIGTERM and `grace_s` to end, then SIGKILL (at once for 0)."""
    if proc.returncode is None and grace_s > 0:
        _signal_group(proc.pid, signal.SIGTERM)
        with contextlib.suppress(TimeoutError):
            await asyncio.wait_for(proc.wait(), grace_s)
    _kill_group(proc.pid)
    await proc.wait()


def _kill_group(pgid: int) -> None:
    _signal_group(pgid, signal.SIGKILL)


def _signal_group(pgid: int, sig: signal.Signals) -> None:
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(pgid, sig)


def _signal_name(number: int) -> str:
    try:
        return signal.Signals(number).name
    except ValueError:
        return str(number)
