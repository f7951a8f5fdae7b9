"""A workspace's folder and environment (workspaces/folder.py): nothing of the server's
environment reaches a workspace, and its README says how to push work back."""

from __future__ import annotations

from pathlib import Path

import pytest

from twinlink.workspaces.folder import environment, prepare
from twinlink.workspaces.process import JupyterProcess, Launch


def test_the_environment_is_built_from_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TWINLINK_ADMIN_TOKEN", "tl_secret")
    monkeypatch.setenv("AWS_SECRET_ACCESS_KEY", "secret")
    env = environment(tmp_path, "http://127.0.0.1:8000", "tl_workspace")
    assert env["TWINLINK_URL"] == "http://127.0.0.1:8000"
    assert env["TWINLINK_TOKEN"] == "tl_workspace"
    assert env["HOME"] == str(tmp_path)
    assert set(env) == {"PATH", "HOME", "LANG", "SHELL", "TERM", "TWINLINK_URL", "TWINLINK_TOKEN"}


def test_the_folder_is_the_users_alone_with_a_readme(tmp_path: Path) -> None:
    root = tmp_path / "workspaces" / "alice"
    prepare(root, "alice")
    assert root.stat().st_mode & 0o077 == 0
    readme = (root / "README.md").read_text()
    assert "user:alice" in readme and "client.library.push" in readme


def test_jupyterlab_listens_on_loopback_under_the_users_path_without_its_token_in_argv(
    tmp_path: Path,
) -> None:
    process = JupyterProcess(Launch("/workspaces/alice/", tmp_path, {}, 0))
    command = process.command()
    assert command[command.index("--ip") + 1] == "127.0.0.1"
    assert "--ServerApp.base_url=/workspaces/alice/" in command
    assert not any(process.token in part for part in command)  # ps shows argv to everyone
