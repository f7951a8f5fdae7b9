"""The local cluster's secrets (twinlink.devcluster.credentials): generated on the first
start, readable by their owner alone, the same on every later start, and a damaged admin
file refused with a message saying what to do."""

from __future__ import annotations

from pathlib import Path

import pytest
from cryptography.fernet import Fernet

from twinlink.devcluster.credentials import ADMIN_FILE, CredentialsError, load_or_create


def test_the_first_start_makes_the_secrets_and_later_starts_find_them(tmp_path: Path) -> None:
    first = load_or_create(tmp_path)
    assert first.created
    Fernet(first.secret_key.encode())  # a key the nodes' vault can use
    assert first.database_password and first.admin_password and first.admin_token
    for name in ("secret-key", "database-password", ADMIN_FILE):
        assert (tmp_path / name).stat().st_mode & 0o777 == 0o600, name
    again = load_or_create(tmp_path)
    assert not again.created
    assert (again.secret_key, again.database_password) == (
        first.secret_key,
        first.database_password,
    )
    assert (again.admin_password, again.admin_token) == (first.admin_password, first.admin_token)


def test_each_cluster_gets_secrets_of_its_own(tmp_path: Path) -> None:
    (tmp_path / "one").mkdir()
    (tmp_path / "other").mkdir()
    one, other = load_or_create(tmp_path / "one"), load_or_create(tmp_path / "other")
    assert one.secret_key != other.secret_key
    assert one.admin_token != other.admin_token


def test_an_admin_file_without_its_token_is_refused_saying_what_to_do(tmp_path: Path) -> None:
    load_or_create(tmp_path)
    (tmp_path / ADMIN_FILE).write_text("username: admin\npassword: x\n")
    with pytest.raises(CredentialsError, match="restore it, or remove the cluster's folder"):
        load_or_create(tmp_path)
