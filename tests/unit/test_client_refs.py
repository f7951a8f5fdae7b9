"""twinlink.client's library references: `[lib:][scope/]kind/name[@ref][#path]`."""

from __future__ import annotations

import pytest

from twinlink.client import AssetRef, parse_ref


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("models/tingen-beam", AssetRef("models", "tingen-beam")),
        ("lib:models/tingen-beam@1.0.0", AssetRef("models", "tingen-beam", version="1.0.0")),
        (
            "lib:common/models/tingen-beam@sha256:ab12#tingen.fmu",
            AssetRef("models", "tingen-beam", "common", "sha256:ab12", "tingen.fmu"),
        ),
        ("group:ntnu/data/runs-2024", AssetRef("data", "runs-2024", "group:ntnu")),
        ("me/twins/rig#lifecycle/create", AssetRef("twins", "rig", "me", path="lifecycle/create")),
    ],
)
def test_references_as_people_write_them(text: str, expected: AssetRef) -> None:
    assert parse_ref(text) == expected


def test_a_bare_name_takes_the_kind_given() -> None:
    assert parse_ref("tingen-rig@2", kind="twins") == AssetRef("twins", "tingen-rig", version="2")


def test_str_writes_the_reference_back() -> None:
    text = "user:ada/models/beam@1.0.0#beam.fmu"
    assert str(parse_ref(text)) == text


@pytest.mark.parametrize(
    ("text", "kind", "says"),
    [
        ("tingen-beam", None, "is not a library reference"),
        ("fmus/beam", None, "the kind 'fmus' is not one of"),
        ("models/Beam", None, "must be lower case"),
        ("everyone/models/beam", None, "the scope 'everyone'"),
        ("a/b/c/d", None, "is not a library reference"),
        ("models/beam", "twins", "is of kind 'models', not 'twins'"),
    ],
)
def test_a_wrong_reference_says_what_is_wrong(text: str, kind: str | None, says: str) -> None:
    with pytest.raises(ValueError, match=says):
        parse_ref(text, kind)


def test_a_reference_without_scope_has_no_url_until_located() -> None:
    ref = parse_ref("models/beam")
    with pytest.raises(AssertionError):
        _ = ref.base
    assert ref.at("common").base == "/api/v1/library/common/models/beam"
