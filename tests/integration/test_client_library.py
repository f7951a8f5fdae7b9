"""twinlink.client's library against a real server: pushes streamed (the same content again
makes no version), a reference without scope found in the caller's space before common,
search finding assets, a held version's delete refused naming its holder, pulls unpacked."""

from __future__ import annotations

import textwrap
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import Server
from tests.integration._fixtures import no_server_errors as no_server_errors  # autouse
from tests.integration._util import make_user, unique
from twinlink.client import ApiError, Client

pytestmark = pytest.mark.integration


@pytest.fixture
def client(server: Server) -> Iterator[Client]:
    with Client(server.url, server.admin_token) as c:
        yield c


def _folder(root: Path, text: str) -> Path:
    (root / "sub").mkdir(parents=True)
    (root / "sub" / "values.txt").write_text(text)
    return root


def test_push_again_tags_and_pull(client: Client, tmp_path: Path) -> None:
    name = unique("set")
    src = _folder(tmp_path / "a", "1 2 3\n")
    first = client.library.push(src, kind="data", name=name, tags=["v1"], description="numbers")
    assert first["created"] is True and first["asset"]["scope"] == "user:admin"
    assert [f["path"] for f in first["version"]["files"]] == ["sub/values.txt"]
    again = client.library.push(src, kind="data", name=name, tags=["v1.0"])
    assert again["created"] is False
    assert again["version"]["digest"] == first["version"]["digest"]
    shown = client.library.show(f"data/{name}")
    assert shown["description"] == "numbers"
    assert set(shown["tags"]) == {"latest", "v1", "v1.0"}
    out = client.library.pull(f"data/{name}@v1.0", tmp_path / "out")
    assert (out / "sub" / "values.txt").read_text() == "1 2 3\n"
    hits = client.search(name)
    assert any(h.get("kind") == "asset" and h["ref"] == f"user:admin/data/{name}" for h in hits)


def test_a_ref_without_scope_is_your_own_before_common(
    server: Server, client: Client, tmp_path: Path
) -> None:
    name = unique("shared")
    client.library.push(_folder(tmp_path / "c", "common\n"), kind="data", name=name,
                        scope="common")  # fmt: skip
    user = unique("ada")
    with Client(server.url, make_user(server, user)) as ada:
        assert ada.library.locate(f"data/{name}").scope == "common"
        ada.library.push(_folder(tmp_path / "o", "own\n"), kind="data", name=name)
        assert ada.library.locate(f"data/{name}").scope == f"user:{user}"
        with pytest.raises(ApiError) as refused:  # common is written by admins and curators
            ada.library.push(tmp_path / "o", kind="data", name=name, scope="common")
        assert refused.value.status == 403
        with pytest.raises(ApiError) as missing:
            ada.library.show(f"data/{unique('none')}")
        assert missing.value.status == 404 and "in your space, your groups' or common" in str(
            missing.value
        )


def test_a_version_a_deployment_uses_cannot_be_deleted(client: Client, tmp_path: Path) -> None:
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "twin.yaml").write_text(textwrap.dedent("""
        description: held
        devices: [{name: d}]
    """))  # fmt: skip
    name = unique("held")
    pushed = client.library.push(pkg, kind="twins", name=name)
    deployment = unique("holder")
    client.deployments.create(f"twins/{name}", deployment)
    digest = pushed["version"]["digest"]
    with pytest.raises(ApiError) as held:
        client.library.rm(f"twins/{name}", version=digest)
    assert held.value.status == 409 and "deployment:" in held.value.detail
    client.deployments.terminate(deployment, purge=True)
    client.library.rm(f"twins/{name}@{digest}")
    assert client.library.versions(f"user:admin/twins/{name}") == []
