"""The per-requirements Python envs of Python FMUs (fmuenv.py): their key, what of the
server's environment pip sees, and the requirements a processor may ask for."""

from __future__ import annotations

import asyncio
from pathlib import Path

import pytest
from pydantic import ValidationError

from twinlink.processors.fmuenv import READY, EnvBuildError, FmuEnvs, env_key, pip_environment
from twinlink.processors.spec import ProcessorSpec


def test_the_same_requirements_in_any_order_share_one_env() -> None:
    assert env_key(["a==1", "b==2"]) == env_key(["b==2", "a==1", "a==1"])
    assert env_key(["a==1"]) != env_key(["a==2"])


def test_pip_sees_the_index_settings_and_no_secret(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PIP_INDEX_URL", "https://mirror.example/simple")
    monkeypatch.setenv("HTTPS_PROXY", "http://proxy.example:3128")
    monkeypatch.setenv("TWINLINK_ADMIN_PASSWORD", "secret")
    monkeypatch.setenv("AWS_SECRET_ACCESS_KEY", "secret")
    env = pip_environment()
    assert env["PIP_INDEX_URL"] == "https://mirror.example/simple"
    assert env["HTTPS_PROXY"] == "http://proxy.example:3128"
    assert "secret" not in env.values()


def test_requirements_are_one_package_each() -> None:
    spec = ProcessorSpec(name="p", blueprint="fmu", python_requirements=[" toolz==1.0.0 "])
    assert spec.python_requirements == ["toolz==1.0.0"]
    for bad in ("-e .", "--index-url=x", "toolz --hash=sha256:0", "", "a\nb"):
        with pytest.raises(ValidationError, match="not a requirement"):
            ProcessorSpec(name="p", blueprint="fmu", python_requirements=[bad])


async def test_a_build_past_its_time_fails_and_fails_again_at_once(tmp_path: Path) -> None:
    envs = FmuEnvs(tmp_path, build_timeout_s=0.01)  # pip cannot even start in that time
    started: list[str] = []
    with pytest.raises(EnvBuildError, match=r"pip install took longer than 0\.01 s"):
        await envs.python(["more-itertools==10.7.0"], started.append)
    assert started == [env_key(["more-itertools==10.7.0"])]
    assert not envs.is_ready(["more-itertools==10.7.0"])
    with pytest.raises(EnvBuildError, match="took longer"):  # not built again
        await envs.python(["more-itertools==10.7.0"], started.append)
    assert len(started) == 1


async def test_two_server_processes_build_one_env_once(tmp_path: Path) -> None:
    """Two FmuEnvs on one folder stand for two server processes on one data dir: the second
    waits on the first's file lock, then finds the env ready."""
    builds: list[Path] = []
    release = asyncio.Event()

    async def build(folder: Path, requirements: list[str]) -> None:
        builds.append(folder)
        await release.wait()
        (folder / "bin").mkdir(parents=True)
        (folder / READY).write_text("{}\n")

    first, second = FmuEnvs(tmp_path), FmuEnvs(tmp_path)
    first._build = second._build = build  # type: ignore[method-assign]
    both = asyncio.gather(first.python(["a==1"]), second.python(["a==1"]))
    for _ in range(1000):  # until one builds (the other waits on the lock), at most 10 s
        if builds:
            break
        await asyncio.sleep(0.01)
    release.set()
    one, two = await both
    assert one == two == tmp_path / env_key(["a==1"]) / "bin" / "python"
    assert len(builds) == 1
