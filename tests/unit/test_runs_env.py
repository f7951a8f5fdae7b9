"""What a run is given: its environment built from nothing but what docs/runs.md lists, how
its script is started (DTaaS scripts often lack the executable bit), and its limits (the
phase's, then the package's default, then the server's)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from twinlink.deploy.runenv import RUN_PATH, env_name, param_text, run_environment
from twinlink.deploy.runner import Limits, command_of, own_files
from twinlink.deploy.runs import PhaseSettings, RunTarget


def _env(work: Path) -> dict[str, str]:
    return run_environment(
        work=work, url="http://127.0.0.1:8000", token="tl_run", twin="rig",
        deployment="rig", phase="analyze", run_id=12,
        params={"zeta": 0.7, "label-text": "the rig", "on": True, "modes": [1, 2]},
        device_tokens={"tingen-SAP": "tl_device"},
    )  # fmt: skip


def test_the_environment_is_built_from_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TWINLINK_SECRET_KEY", "never-seen")
    monkeypatch.setenv("TWINLINK_STORE_URL", "postgresql://u:p@h/db")
    env = _env(tmp_path)
    assert env == {
        "PATH": RUN_PATH,
        "HOME": str(tmp_path),
        "LANG": "C.UTF-8",
        "TWINLINK_URL": "http://127.0.0.1:8000",
        "TWINLINK_TOKEN": "tl_run",
        "TWINLINK_TWIN": "rig",
        "TWINLINK_DEPLOYMENT": "rig",
        "TWINLINK_PHASE": "analyze",
        "TWINLINK_RUN_ID": "12",
        "TWINLINK_PARAMS": json.dumps(
            {"zeta": 0.7, "label-text": "the rig", "on": True, "modes": [1, 2]}
        ),
        "TWINLINK_PARAM_ZETA": "0.7",
        "TWINLINK_PARAM_LABEL_TEXT": "the rig",
        "TWINLINK_PARAM_ON": "true",
        "TWINLINK_PARAM_MODES": "[1, 2]",
        "TWINLINK_DEVICE_TOKEN_TINGEN_SAP": "tl_device",
    }
    assert "never-seen" not in json.dumps(env)
    assert env_name("a.b c-d") == "A_B_C_D" and param_text("x") == "x" and param_text(3) == "3"


def test_a_script_runs_with_its_interpreter_else_sh(tmp_path: Path) -> None:
    def script(name: str, head: bytes, mode: int = 0o644) -> Path:
        path = tmp_path / name
        path.write_bytes(head + b"echo hi\n")
        os.chmod(path, mode)
        return path

    plain = script("plain", b"")
    assert command_of(plain) == ["/bin/sh", str(plain)]
    bash = script("bash", b"#!/bin/bash -e\n")  # not executable: its #! line still counts
    assert command_of(bash) == ["/bin/bash", "-e", str(bash)]
    env = script("env", b"#!/usr/bin/env python3 -u\n", 0o755)
    assert command_of(env) == ["/usr/bin/env", "python3 -u", str(env)]  # as the kernel does
    empty = script("empty", b"#!\n")
    assert command_of(empty) == ["/bin/sh", str(empty)]
    binary = script("binary", b"\x7fELF\x02\x01", 0o755)
    assert command_of(binary) == [str(binary)]


def test_a_phases_limits_are_its_own_then_the_packages_then_the_servers() -> None:
    async def prepare(work: Path) -> None:
        pass

    target = RunTarget(
        deployment_id=1, deployment="rig", twin="rig", owner_id=1, prepare=prepare,
        lifecycle={"default": PhaseSettings(timeout_s=600), "execute": PhaseSettings(0, 64)},
    )  # fmt: skip
    server = Limits(3600, 2048)
    assert target.limits("execute", server) == Limits(0, 64)
    assert target.limits("analyze", server) == Limits(600, 2048)
    assert RunTarget(1, "rig", "rig", 1, prepare).limits("create", server) == server


def test_the_working_dirs_hard_links_become_the_runs_own_copies(tmp_path: Path) -> None:
    blob = tmp_path / "blob"
    blob.write_text("as pushed\n")
    os.chmod(blob, 0o444)
    work = tmp_path / "work"
    (work / "sub").mkdir(parents=True)
    os.link(blob, work / "sub" / "config.json")
    (work / "own.txt").write_text("mine\n")
    assert own_files(work) == 1
    copy = work / "sub" / "config.json"
    assert copy.read_text() == "as pushed\n" and os.stat(copy).st_nlink == 1
    assert os.stat(copy).st_mode & 0o777 == 0o444 and os.stat(blob).st_nlink == 1
    os.chmod(copy, 0o644)
    copy.write_text("changed\n")
    assert blob.read_text() == "as pushed\n"
