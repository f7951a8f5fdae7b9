"""The test hygiene plug-in (tests/_hygiene.py), on a small test tree of its own that pytest runs
in a child process: a leak fails the test that made it and is cleaned up, what a module's
fixtures own is the module's, integration modules carry their marker, unit tests build nothing."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
from dataclasses import dataclass

import psutil
import pytest

from tests.conftest import ROOT

CONFTEST = """
import pytest

@pytest.fixture
def fmu_files() -> None:
    pass
"""

LEAKS = """
import asyncio, os, subprocess, sys, threading
from pathlib import Path

KEPT = []

async def test_a_task_left_pending():
    KEPT.append(asyncio.create_task(asyncio.Event().wait(), name="left-pending"))

def test_a_thread_left_running():
    threading.Thread(target=threading.Event().wait, name="left-running", daemon=True).start()

def test_a_child_left_running():
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"])
    KEPT.append(child)
    Path(os.environ["CHILD_PID_FILE"]).write_text(str(child.pid))

async def test_a_task_that_ends_on_its_own_is_no_leak():
    KEPT.append(asyncio.create_task(asyncio.sleep(0)))

async def test_what_a_test_stops_is_no_leak():
    task = asyncio.create_task(asyncio.Event().wait())
    task.cancel()
    await asyncio.gather(task, return_exceptions=True)
    await asyncio.to_thread(print, "in the loop's executor")
    thread = threading.Thread(target=print)
    thread.start()
    thread.join()
    subprocess.run([sys.executable, "-c", "pass"], check=True)
"""

MODULE_OWNED = """
import asyncio, threading
import pytest
import pytest_asyncio

pytestmark = pytest.mark.asyncio(loop_scope="module")

@pytest.fixture(scope="module")
def worker():
    stop = threading.Event()
    thread = threading.Thread(target=stop.wait, name="module-worker")
    thread.start()
    yield
    stop.set()
    thread.join()

@pytest_asyncio.fixture(scope="module", loop_scope="module", autouse=True)
async def ticker():
    task = asyncio.create_task(asyncio.Event().wait(), name="module-ticker")
    yield
    task.cancel()

async def test_one(worker):
    await asyncio.to_thread(print, "a worker of the module's loop")

async def test_two(worker):
    pass
"""

MODULE_LEAK = """
import threading
import pytest

@pytest.fixture(scope="module")
def forgetful():
    threading.Thread(target=threading.Event().wait, name="module-leak", daemon=True).start()

def test_uses_it(forgetful):
    pass
"""

# A module's process (a server's stand-in) starts a child of its own for each line it reads
# (a worker) and stops them at its end; the test starts one too and leaves it.
SPAWNS = """
import os, subprocess, sys
from pathlib import Path
import pytest

SPAWNER = '''
import subprocess, sys
kids = []
for line in sys.stdin:
    kids.append(subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"]))
    print(kids[-1].pid, flush=True)
for kid in kids:
    kid.kill()
    kid.wait()
'''
KEPT = []

def start_spawner():
    return subprocess.Popen([sys.executable, "-c", SPAWNER], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True)

def spawn(spawner):
    spawner.stdin.write("\\n")
    spawner.stdin.flush()
    return int(spawner.stdout.readline())

def note(name, pid):
    (Path(os.environ["PID_DIR"]) / f"{name}.pid").write_text(str(pid))

@pytest.fixture(scope="module")
def spawner():
    spawner = start_spawner()
    yield spawner
    spawner.stdin.close()  # it stops its children and ends
    spawner.wait(timeout=60)
    spawner.stdout.close()

def test_what_a_modules_process_starts_is_its_own(spawner):
    note("worker", spawn(spawner))

def test_what_the_test_starts_is_the_tests_beside_them(spawner):
    note("other-worker", spawn(spawner))
    own = start_spawner()
    KEPT.append(own)
    note("own", own.pid)
    note("own-child", spawn(own))
"""

BUILDS = """
import subprocess
import pytest

def test_runs_gcc():
    subprocess.run(["gcc", "--version"], check=False)

def test_asks_for_fmu_files(fmu_files):
    pass

@pytest.mark.integration
def test_marked_integration():
    pass

def test_runs_python():
    import sys
    subprocess.run([sys.executable, "-c", "pass"], check=True)
"""

MARKED = """
import pytest

pytestmark = pytest.mark.integration

def test_marked():
    pass
"""


INI = """
[pytest]
asyncio_mode = auto
asyncio_default_fixture_loop_scope = function
markers = integration: starts real servers on loopback
cleanup_settle_s = 1
"""

TREE = {
    "pytest.ini": INI,
    "conftest.py": CONFTEST,
    "tests/unit/test_leaks.py": LEAKS,
    "tests/unit/test_module_owned.py": MODULE_OWNED,
    "tests/unit/test_module_leak.py": MODULE_LEAK,
    "tests/unit/test_spawns.py": SPAWNS,
    "tests/unit/test_builds.py": BUILDS,
    "tests/integration/test_marked.py": MARKED,
    "tests/integration/test_unmarked.py": "def test_unmarked():\n    pass\n",
}


@dataclass
class Outcome:
    output: pytest.LineMatcher
    counts: dict[str, int]
    child_pid: int
    pids: dict[str, int]  # test_spawns.py's processes, by the name it gave them


@pytest.fixture(scope="module")
def outcome(tmp_path_factory: pytest.TempPathFactory) -> Outcome:
    """The tree above, run once by pytest with the plug-in, in a child process."""
    tree = tmp_path_factory.mktemp("tree")
    for name, text in TREE.items():
        (tree / name).parent.mkdir(parents=True, exist_ok=True)
        (tree / name).write_text(textwrap.dedent(text))
    pid_file = tree / "child.pid"
    pid_dir = tree / "pids"
    pid_dir.mkdir()
    env = {**os.environ, "PYTHONPATH": str(ROOT), "CHILD_PID_FILE": str(pid_file),
           "PID_DIR": str(pid_dir)}  # fmt: skip
    env.pop("PYTEST_ADDOPTS", None)
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "tests._hygiene", "-p", "no:cacheprovider", "-rA"],
        cwd=tree, env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    lines = done.stdout.splitlines()
    counts = {kind: int(n) for n, kind in re.findall(r"(\d+) (\w+)", lines[-1])}
    pids = {path.stem: int(path.read_text()) for path in pid_dir.glob("*.pid")}
    return Outcome(pytest.LineMatcher(lines), counts, int(pid_file.read_text()), pids)


def _still_running(pid: int) -> bool:
    try:
        process = psutil.Process(pid)
        return "time.sleep(600)" in " ".join(process.cmdline())
    except psutil.Error:
        return False


def test_leaks_fail_their_test_and_are_cleaned_up(outcome: Outcome) -> None:
    pid = outcome.child_pid
    try:
        outcome.output.fnmatch_lines_random(
            [
                "*ERROR at teardown of test_a_task_left_pending*",
                "*the test left running: asyncio task <Task pending name='left-pending'*",
                "*ERROR at teardown of test_a_thread_left_running*",
                "*the test left running: thread <Thread(left-running, started daemon*",
                "*ERROR at teardown of test_a_child_left_running*",
                f"*the test left running: child process {pid} (*time.sleep(600))*",
                "*ERROR at teardown of test_uses_it*",
                "*the fixtures of test_module_leak.py left running: thread <Thread(module-leak*",
            ]
        )
        assert not _still_running(pid)  # killed, not left to outlive the session
    finally:
        if _still_running(pid):
            psutil.Process(pid).kill()
    # errors: 4 tests' leaks and a module's, fmu_files in a unit test, a unit test marked
    # integration, the unmarked integration module; failed: the unit test that runs gcc
    # (a test with an error at its teardown counts as passed too)
    assert outcome.counts == {"passed": 12, "failed": 1, "errors": 8}, outcome.counts


def test_a_process_the_test_starts_is_its_own_and_what_it_starts_too(outcome: Outcome) -> None:
    own, own_child = outcome.pids["own"], outcome.pids["own-child"]
    outcome.output.fnmatch_lines_random(
        [
            "*ERROR at teardown of test_what_the_test_starts_is_the_tests_beside_them*",
            f"*the test left running: *child process {own} (*",
            f"*the test left running: *child process {own_child} (*time.sleep(600)*",
        ]
    )
    assert not _still_running(own_child)


def test_what_a_process_that_ran_before_the_test_starts_is_not_the_tests(
    outcome: Outcome,
) -> None:
    """A module's server starts processor workers while a test runs: they are the server's."""
    outcome.output.fnmatch_lines(
        ["PASSED tests/unit/test_spawns.py::test_what_a_modules_process_starts_is_its_own"]
    )
    outcome.output.no_fnmatch_line("ERROR tests/unit/test_spawns.py::test_what_a_modules_*")
    for worker in (outcome.pids["worker"], outcome.pids["other-worker"]):
        outcome.output.no_fnmatch_line(f"*child process {worker} (*")
    # the module's process stopped them, so its fixtures left nothing either
    outcome.output.no_fnmatch_line("*the fixtures of test_spawns.py left running*")


def test_what_ends_or_is_stopped_and_what_a_module_owns_pass(outcome: Outcome) -> None:
    for test in [
        "tests/unit/test_leaks.py::test_a_task_that_ends_on_its_own_is_no_leak",
        "tests/unit/test_leaks.py::test_what_a_test_stops_is_no_leak",
        "tests/unit/test_module_owned.py::test_one",
        "tests/unit/test_module_owned.py::test_two",
        "tests/unit/test_builds.py::test_runs_python",
        "tests/integration/test_marked.py::test_marked",
    ]:
        outcome.output.fnmatch_lines([f"PASSED {test}"])
        outcome.output.no_fnmatch_line(f"ERROR {test} *")


def test_integration_modules_carry_their_marker_and_unit_tests_build_nothing(
    outcome: Outcome,
) -> None:
    outcome.output.fnmatch_lines_random(
        [
            "*test_unmarked.py has no `pytestmark = pytest.mark.integration` below its imports*",
            "*unit tests build nothing, and this one runs gcc*",
            "*test_builds.py: unit tests build nothing, and fmu_files compiles FMUs*",
            "*test_builds.py: a unit test marked integration belongs in tests/integration*",
        ]
    )
