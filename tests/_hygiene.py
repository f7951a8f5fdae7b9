"""Test hygiene, a pytest plug-in the root conftest loads.

- A test leaves nothing running (as Home Assistant's `verify_cleanup`): no task of its asyncio
  event loop, no thread, no child process that was not there before it. What a module-scoped
  fixture starts (a server shared by the module's tests) belongs to the module: it is checked
  the same way once the module's fixtures are torn down. So does what such a process starts
  while a test runs (the server's processor workers): a process is the test's only when no
  process that ran before the test is its ancestor. A leak fails the test (an error at its
  teardown) naming what was left, and is then cleaned up where it can be (tasks cancelled,
  processes killed), so the next test starts clean. What ends on its own within
  `cleanup_settle_s` (a server's handler finishing its close) is not a leak.
- Every module under tests/integration carries `pytestmark = pytest.mark.integration`, so that
  `-m "not integration"` leaves out what starts servers; no unit test carries it.
- Unit tests build nothing: a unit test that runs a compiler or make, or asks for `fmu_files`,
  fails (builds belong with the integration tests).
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import sys
import threading
import time
import weakref
from collections.abc import Generator, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import psutil
import pytest
import pytest_asyncio

# The workers of an event loop's default executor (asyncio.to_thread) are named "asyncio_0",
# ...; they stay until their loop closes, so they are the loop's, not a test's.
EXECUTOR_THREAD = "asyncio_"
BUILD_TOOLS = frozenset({"cc", "c++", "gcc", "g++", "clang", "clang++", "make", "cmake", "ninja"})
_REPORTED: weakref.WeakSet[threading.Thread] = weakref.WeakSet()


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addini(
        "cleanup_settle_s",
        "seconds a task, thread or child process a test left may take to end on its own "
        "before it is a leak",
        default="5",
    )


def pytest_configure(config: pytest.Config) -> None:
    sys.addaudithook(_refuse_builds)


# -- what runs ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class Running:
    """What runs in this process at one moment: threads, child processes, a loop's tasks."""

    threads: frozenset[threading.Thread]
    children: Mapping[int, int]  # this process's descendants: pid -> its parent's pid
    tasks: frozenset[asyncio.Task[Any]]

    @classmethod
    def now(cls, loop: asyncio.AbstractEventLoop | None) -> Running:
        tasks = asyncio.all_tasks(loop) if loop is not None and not loop.is_closed() else set()
        return cls(frozenset(threading.enumerate()), child_pids(), frozenset(tasks))


def child_pids() -> dict[int, int]:
    """This process's children and theirs, each with its parent's pid. Read from
    /proc/PID/task/TID/children: psutil's `children()` reads every process of the machine
    (2 ms, twice a test)."""
    if not Path("/proc/self/task").is_dir():
        return _child_pids_by_psutil()
    found: dict[int, int] = {}
    parents = [os.getpid()]
    while parents:
        parent = parents.pop()
        try:
            tids = os.listdir(f"/proc/{parent}/task")
        except OSError:  # it ended meanwhile
            continue
        for tid in tids:
            try:
                with open(f"/proc/{parent}/task/{tid}/children") as f:
                    children = [pid for pid in map(int, f.read().split()) if pid not in found]
            except OSError:
                continue
            found.update(dict.fromkeys(children, parent))
            parents.extend(children)
    return found


def _child_pids_by_psutil() -> dict[int, int]:
    found: dict[int, int] = {}
    for process in psutil.Process().children(recursive=True):
        with contextlib.suppress(psutil.Error):
            found[process.pid] = process.ppid()
    return found


def started_since(before: Mapping[int, int], now: Mapping[int, int]) -> list[int]:
    """The processes of `now` that were started since `before` by this process itself, or by
    one it started since: a process that ran before (a module's server) owns what it starts
    meanwhile (its workers), however deep, and its fixture answers for them."""
    mine: list[int] = []
    for pid in now.keys() - before.keys():
        parent, hops = now[pid], 0
        # up the tree to this process (not in `now`) or to one that ran before; the hops bound
        # the walk should a reused pid ever make a loop of what was read
        while parent in now and parent not in before and hops < len(now):
            parent, hops = now[parent], hops + 1
        if parent not in before:
            mine.append(pid)
    return mine


# -- leaks -------------------------------------------------------------------------------------


def leaks(
    before: Running, loop: asyncio.AbstractEventLoop | None, settle_s: float, *, own_loop: bool
) -> list[str]:
    """What runs now that did not run `before` and does not end within `settle_s`, described;
    tasks are cancelled and processes killed (threads cannot be). `own_loop`: the loop closes
    after this check, so its executor is shut down here and its workers must end with it."""
    deadline = time.monotonic() + settle_s
    found = _leaked_tasks(before.tasks, loop, settle_s)
    if own_loop and loop is not None and not loop.is_closed():
        loop.run_until_complete(loop.shutdown_default_executor())
    found += _leaked_threads(before.threads, deadline, executor_too=own_loop)
    found += _leaked_children(before.children, deadline)
    return found


def _leaked_tasks(
    before: frozenset[asyncio.Task[Any]], loop: asyncio.AbstractEventLoop | None, settle_s: float
) -> list[str]:
    if loop is None or loop.is_closed():
        return []
    new = asyncio.all_tasks(loop) - before
    if new:
        loop.run_until_complete(asyncio.wait(new, timeout=settle_s))
    left = [task for task in new if not task.done()]
    described = [f"asyncio task {task!r}" for task in left]
    for task in left:
        task.cancel()
    if left:
        loop.run_until_complete(asyncio.wait(left, timeout=settle_s))
    return described


def _leaked_threads(
    before: frozenset[threading.Thread], deadline: float, *, executor_too: bool
) -> list[str]:
    new = [
        thread
        for thread in threading.enumerate()
        if thread not in before
        and thread not in _REPORTED
        # a thread started outside Python (a C library calling back) is not ours to join
        and not isinstance(thread, threading._DummyThread)
        and (executor_too or not thread.name.startswith(EXECUTOR_THREAD))
    ]
    for thread in new:
        thread.join(max(0.0, deadline - time.monotonic()))
    left = [thread for thread in new if thread.is_alive()]
    _REPORTED.update(left)  # it cannot be stopped: blame only the test that started it
    return [f"thread {thread!r}" for thread in left]


def _leaked_children(before: Mapping[int, int], deadline: float) -> list[str]:
    new = [p for pid in started_since(before, child_pids()) if (p := _process(pid)) is not None]
    while (alive := [p for p in new if _alive(p)]) and time.monotonic() < deadline:
        time.sleep(0.05)  # polling the processes' real state
    described = [f"child process {_describe(p)}" for p in alive]
    tree = [child for p in alive for child in _with_children(p)]
    for p in tree:
        with contextlib.suppress(psutil.Error):
            p.kill()
    psutil.wait_procs(tree, timeout=10)
    return described


def _process(pid: int) -> psutil.Process | None:
    try:
        return psutil.Process(pid)
    except psutil.Error:
        return None


def _alive(process: psutil.Process) -> bool:
    """Running code: one that has ended but is not yet waited for is not (Python warns of those
    itself, with a ResourceWarning)."""
    try:
        return bool(process.status() != psutil.STATUS_ZOMBIE)
    except psutil.Error:
        return False


def _with_children(process: psutil.Process) -> list[psutil.Process]:
    try:
        return [*process.children(recursive=True), process]
    except psutil.Error:
        return [process]


def _describe(process: psutil.Process) -> str:
    try:
        command = " ".join(process.cmdline()) or process.name()
    except psutil.Error:
        command = "?"
    # on one line (`python -c` with a script of several), so the message stays one line
    return f"{process.pid} ({' '.join(command.split())[:200]})"


def _fail_on(found: list[str], who: str) -> None:
    if found:
        pytest.fail(
            f"{who} left running: {'; '.join(found)}. Stop what a test starts before it ends "
            "(cancel and await tasks, join threads, terminate and wait for processes, in a "
            "finally or a fixture's teardown); these were cancelled or killed now.",
            pytrace=False,
        )


# -- the checks --------------------------------------------------------------------------------


def _settle_s(config: pytest.Config) -> float:
    return float(config.getini("cleanup_settle_s"))


def _runner_loop(request: pytest.FixtureRequest, scope: str) -> asyncio.AbstractEventLoop:
    """The loop of that scope. pytest-asyncio (1.x) keeps each loop in a runner fixture named
    after its scope; asking for it here sets it up before the fixture that asks, so it is torn
    down (and its tasks cancelled without a word) only after that fixture's check."""
    runner: asyncio.Runner = request.getfixturevalue(f"_{scope}_scoped_runner")
    return runner.get_loop()


def _loop_scope(node: pytest.Item | pytest.Collector, config: pytest.Config) -> str:
    marker = node.get_closest_marker("asyncio")
    scope = marker.kwargs.get("loop_scope") if marker is not None else None
    return str(scope or config.getini("asyncio_default_test_loop_scope") or "function")


@pytest.fixture(autouse=True)
def verify_cleanup(request: pytest.FixtureRequest) -> Iterator[None]:
    """Fails a test that leaves a task, thread or child process running (see the docstring of
    tests/_hygiene.py)."""
    loop, own_loop = None, True
    if pytest_asyncio.is_async_test(request.node):
        scope = _loop_scope(request.node, request.config)
        loop, own_loop = _runner_loop(request, scope), scope == "function"
    before = Running.now(loop)
    yield
    _fail_on(leaks(before, loop, _settle_s(request.config), own_loop=own_loop), "the test")


@pytest.fixture(autouse=True, scope="module")
def verify_module_cleanup(request: pytest.FixtureRequest) -> Iterator[None]:
    """The same for what the module's fixtures start, once they are torn down (its loop's
    tasks too, when the module's tests share one loop)."""
    shared = _loop_scope(request.node, request.config) == "module"
    loop = _runner_loop(request, "module") if shared else None
    before = Running.now(loop)
    yield
    found = leaks(before, loop, _settle_s(request.config), own_loop=True)
    _fail_on(found, f"the fixtures of {request.node.name}")


# -- integration or unit -------------------------------------------------------------------------


def _kind(item: pytest.Item) -> str | None:
    """The kind of a test under tests/integration or tests/unit: "integration" or "unit"."""
    try:
        parts = item.path.relative_to(item.config.rootpath).parts
    except ValueError:
        return None
    if parts[:1] == ("tests",) and len(parts) > 2 and parts[1] in ("integration", "unit"):
        return parts[1]
    return None


def _module_marked(item: pytest.Item) -> bool:
    module = item.getparent(pytest.Module)
    marks = getattr(module.obj, "pytestmark", []) if module is not None else []
    marks = marks if isinstance(marks, list) else [marks]
    return any(mark.name == "integration" for mark in marks)


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item: pytest.Item) -> None:
    kind = _kind(item)
    where = item.path.relative_to(item.config.rootpath) if kind else None
    if kind == "integration" and not _module_marked(item):
        pytest.fail(
            f"{where} has no `pytestmark = pytest.mark.integration` below its imports: every "
            'module in tests/integration carries it, so that -m "not integration" leaves it out',
            pytrace=False,
        )
    if kind == "unit" and item.get_closest_marker("integration") is not None:
        pytest.fail(
            f"{where}: a unit test marked integration belongs in tests/integration", pytrace=False
        )
    if kind == "unit" and "fmu_files" in getattr(item, "fixturenames", ()):
        pytest.fail(
            f"{where}: unit tests build nothing, and fmu_files compiles FMUs with gcc; "
            "move the test to tests/integration",
            pytrace=False,
        )


class _Builds:
    """Whether a unit test runs now (its fixtures' setup and teardown included)."""

    refused = False


@pytest.hookimpl(wrapper=True)
def pytest_runtest_protocol(item: pytest.Item) -> Generator[None, object, object]:
    _Builds.refused = _kind(item) == "unit"
    try:
        return (yield)
    finally:
        _Builds.refused = False


def _refuse_builds(event: str, args: tuple[Any, ...]) -> None:
    """An audit hook: every new program is announced as "subprocess.Popen" (executable, args,
    cwd, env) before it starts; raising stops it."""
    if event != "subprocess.Popen" or not _Builds.refused:
        return
    program = Path(os.fsdecode(args[0])).name
    if program in BUILD_TOOLS:
        pytest.fail(
            f"unit tests build nothing, and this one runs {program}: move it (or the fixture "
            "that builds) to tests/integration"
        )
