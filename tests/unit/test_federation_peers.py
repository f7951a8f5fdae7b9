"""Peers' tokens (federation/peers.py): stored sealed by origin, read back with the same
key only, never shown."""

from __future__ import annotations

import stat
from pathlib import Path

import pytest
from cryptography.fernet import Fernet

from twinlink.auth.vault import Vault, VaultError
from twinlink.domain.errors import InvalidInputError
from twinlink.federation.peers import PEERS_FILE, Peers, peer_origin


def test_a_peer_is_its_origin() -> None:
    assert peer_origin("B.Example.org") == "https://b.example.org"
    assert peer_origin("b.example.org:443") == "https://b.example.org"
    assert peer_origin("127.0.0.1:8001", "http") == "http://127.0.0.1:8001"
    assert peer_origin("https://b.example.org/") == "https://b.example.org"
    for bad in ("b.example.org/twins", "ftp://b.example.org", "https://", "b.example.org?x=1"):
        with pytest.raises(InvalidInputError):
            peer_origin(bad)


def test_tokens_are_sealed_on_disk_and_read_back_with_the_key(tmp_path: Path) -> None:
    key = Fernet.generate_key()
    peers = Peers(Vault(key), tmp_path)
    assert peers.put("b.example.org", "tl_secret_one") == "https://b.example.org"
    peers.put("127.0.0.1:8001", "tl_secret_two", "http")
    stored = (tmp_path / PEERS_FILE).read_bytes()
    assert b"tl_secret" not in stored and b"example" not in stored
    assert stat.S_IMODE((tmp_path / PEERS_FILE).stat().st_mode) == 0o600
    again = Peers(Vault(key), tmp_path)
    assert again.origins() == ["http://127.0.0.1:8001", "https://b.example.org"]
    assert again.token_for("https://b.example.org") == "tl_secret_one"
    assert again.token_for("http://b.example.org") is None  # another origin: no token
    assert again.token_for("https://b.example.org:8443") is None
    assert "tl_secret" not in repr(again)
    with pytest.raises(VaultError):
        Peers(Vault(Fernet.generate_key()), tmp_path)


def test_forgetting_a_peer(tmp_path: Path) -> None:
    peers = Peers(Vault(Fernet.generate_key()), tmp_path)
    peers.put("b.example.org", "t1")
    peers.put("b.example.org", "t2", "http")
    assert sorted(peers.delete("b.example.org")) == [
        "http://b.example.org",
        "https://b.example.org",
    ]
    assert peers.delete("b.example.org") == []
    assert peers.origins() == []


@pytest.mark.parametrize("token", ["", "has space", "x" * 4097])
def test_a_token_must_be_one_word(tmp_path: Path, token: str) -> None:
    with pytest.raises(InvalidInputError, match="without spaces"):
        Peers(Vault(Fernet.generate_key()), tmp_path).put("b.example.org", token)
