"""A Python FMU (pythonfmu) whose code imports a package the server does not have, on a real
server: with `python_requirements` its worker runs in a virtualenv of its own, built once by
pip from the package index; without them the FMU's own import error is in the worker's logs;
a requirement pip cannot install fails the processor once, with pip's words, not in a loop."""

from __future__ import annotations

import importlib.util
import io
import os
import subprocess
import sys
import tarfile
from pathlib import Path

import pytest

from tests.conftest import Server
from tests.integration._live import device_twin
from tests.integration._processors import (
    MS,
    create,
    events,
    post,
    samples_until,
    wait_for,
    watching,
)
from tests.integration._processors import server as server  # module fixture
from tests.integration._util import assert_problem, unique

pytestmark = pytest.mark.integration

MODEL = Path(__file__).parents[1] / "fmus" / "python_tripler" / "Tripler.py"
PACKAGE = "more_itertools"  # what the FMU imports, and the server must not have
REQUIREMENT = "more-itertools==10.7.0"  # pure Python, one small wheel


@pytest.fixture(scope="module")
def tripler(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Tripler.fmu, built with pythonfmu. Building imports the model, so it is built with a
    stand-in `more_itertools` on its path; the FMU carries only the model's source."""
    assert importlib.util.find_spec(PACKAGE) is None, f"the server's Python has {PACKAGE}"
    folder = tmp_path_factory.mktemp("tripler")
    (folder / "stub").mkdir()
    (folder / "stub" / f"{PACKAGE}.py").write_text("def ilen(items): return len(items)\n")
    env = {**os.environ, "PYTHONPATH": str(folder / "stub")}
    subprocess.run(
        [sys.executable, "-m", "pythonfmu", "build", "-f", str(MODEL), "-d", str(folder)],
        check=True, env=env, capture_output=True,
    )  # fmt: skip
    return folder / "Tripler.fmu"


def upload(server: Server, slug: str, path: Path) -> None:
    with server.admin as admin:
        r = admin.put(f"/api/v1/twins/{slug}/fmus/{path.name}", content=path.read_bytes())
    assert r.status_code == 201, r.text


def logs(server: Server, slug: str, name: str) -> str:
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/processors/{name}/logs")
    assert r.status_code == 200, r.text
    return "\n".join(line["text"] for line in r.json()["lines"])


def push_model(server: Server, name: str, files: dict[str, bytes]) -> None:
    """Push `files` as version 1.0.0 of the library's common/models/<name> (a tar)."""
    data = io.BytesIO()
    with tarfile.open(fileobj=data, mode="w") as tar:
        for path, content in files.items():
            info = tarfile.TarInfo(path)
            info.size = len(content)
            tar.addfile(info, io.BytesIO(content))
    with server.admin as admin:
        r = admin.post(
            f"/api/v1/library/common/models/{name}/versions",
            params={"format": "tar", "tag": "1.0.0"}, content=data.getvalue(),
        )  # fmt: skip
    assert r.status_code in (200, 201), r.text


def tripler_spec(
    name: str, requirements: list[str] | None, fmu: str = "Tripler.fmu"
) -> dict[str, object]:
    spec: dict[str, object] = {
        "name": name, "blueprint": "fmu", "inputs": {"x": "force"},
        "params": {"fmu": fmu, "outputs": ["y"]},
    }  # fmt: skip
    if requirements is not None:
        spec["python_requirements"] = requirements
    return spec


def test_a_python_fmu_runs_in_its_own_env_built_once(server: Server, tripler: Path) -> None:
    slug, [device] = device_twin(server)
    upload(server, slug, tripler)
    made = create(server, slug, **tripler_spec("tripler", [REQUIREMENT]))
    assert made["python_requirements"] == [REQUIREMENT]
    wait_for(server, slug, "tripler", lambda p: p["state"] == "running")
    [building] = events(server, slug, "tripler", "env_building")
    assert len(events(server, slug, "tripler", "env_ready")) == 1
    env = server.data_dir / "fmu-envs" / building["data"]["env"]
    assert (env / "ready").is_file()
    assert list(env.glob(f"lib/python*/site-packages/{PACKAGE}/__init__.py"))
    with watching(server, slug, "tripler") as ws:
        post(server, device, 1, [{"force": float(i)} for i in range(5)])
        got = samples_until(ws, lambda s: len(s) >= 5)
    # the first sample is the FMU at its start time, before a step: y's start value
    assert [s["values"]["y"] for s in got] == [0.0] + [2.0 * i + 3 for i in range(1, 5)]
    assert got[1]["time"] - got[0]["time"] == MS

    # Another processor asking for the same requirements uses the same env, without a build.
    create(server, slug, **tripler_spec("again", [f" {REQUIREMENT}"]))
    wait_for(server, slug, "again", lambda p: p["state"] == "running")
    assert events(server, slug, "again", "env_building") == []
    assert [p.name for p in (server.data_dir / "fmu-envs").iterdir() if p.is_dir()] == [env.name]


def test_without_its_requirements_the_fmus_import_error_is_in_its_logs(
    server: Server, tripler: Path
) -> None:
    slug, _ = device_twin(server)
    upload(server, slug, tripler)
    create(server, slug, **tripler_spec("bare", None))
    wait_for(server, slug, "bare", lambda p: p["stats"]["restarts"] >= 1)
    assert f"No module named '{PACKAGE}'" in logs(server, slug, "bare")


def test_a_requirement_pip_cannot_install_fails_the_processor_once(
    server: Server, tripler: Path
) -> None:
    slug, _ = device_twin(server)
    upload(server, slug, tripler)
    create(server, slug, **tripler_spec("unbuildable", ["more-itertools==0.0.0.0"]))
    failed = wait_for(server, slug, "unbuildable", lambda p: p["state"] == "failed")
    assert "could not be built" in failed["last_error"]
    assert "No matching distribution found for more-itertools==0.0.0.0" in failed["last_error"]
    assert failed["stats"]["restarts"] == 0 and failed["pid"] is None
    [event] = events(server, slug, "unbuildable", "failed")
    assert "pip install failed" in event["message"]
    # Given requirements pip can install, it starts again (with the env built before).
    with server.admin as admin:
        r = admin.patch(
            f"/api/v1/twins/{slug}/processors/unbuildable",
            json={"python_requirements": [REQUIREMENT]},
        )
    assert r.status_code == 200, r.text
    again = wait_for(server, slug, "unbuildable", lambda p: p["state"] == "running")
    assert again["stats"]["crashes"] == 0


@pytest.mark.parametrize(
    "requirement", ["--index-url=https://example.invalid/simple", "-r /etc/passwd",
                    "more-itertools --global-option=x", ""],
)  # fmt: skip
def test_pip_options_are_refused_at_create(server: Server, requirement: str) -> None:
    slug, _ = device_twin(server)
    with server.admin as admin:
        r = admin.post(
            f"/api/v1/twins/{slug}/processors",
            json={"name": "opts", "blueprint": "fmu", "params": {"fmu": "Tripler.fmu"},
                  "python_requirements": [requirement]},
        )  # fmt: skip
    problem = assert_problem(r, 422)
    assert "not a requirement" in str(problem)


def test_a_library_model_brings_its_requirements_txt(server: Server, tripler: Path) -> None:
    name = unique("tripler")
    requirements = f"# the model's imports\n\n{REQUIREMENT}  # pure Python\n".encode()
    push_model(server, name, {"fmu/Tripler.fmu": tripler.read_bytes(),
                              "fmu/requirements.txt": requirements})  # fmt: skip
    slug, [device] = device_twin(server)
    create(server, slug, **tripler_spec("lib", None, f"lib:models/{name}@1.0.0#fmu/Tripler.fmu"))
    wait_for(server, slug, "lib", lambda p: p["state"] == "running")
    with watching(server, slug, "lib") as ws:
        post(server, device, 1, [{"force": 0.0}, {"force": 10.0}])
        got = samples_until(ws, lambda s: len(s) >= 2)
    assert got[1]["values"]["y"] == 23.0


def test_a_library_model_with_pip_options_in_requirements_txt_is_refused(
    server: Server, tripler: Path
) -> None:
    name = unique("tripler")
    options = b"--extra-index-url https://example.invalid\n"
    push_model(server, name, {"Tripler.fmu": tripler.read_bytes(), "requirements.txt": options})
    slug, _ = device_twin(server)
    with server.admin as admin:
        r = admin.post(
            f"/api/v1/twins/{slug}/processors",
            json=tripler_spec("lib", None, f"lib:models/{name}@1.0.0#Tripler.fmu"),
        )
    problem = assert_problem(r, 422)
    assert "requirements.txt" in problem["detail"] and "line 1" in problem["detail"]
