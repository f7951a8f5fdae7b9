"""What a run's token (scope `twin:<slug>`) may reach: its twin's API and gateway paths and
library reads; nothing else, however the path is spelled; and nowhere without a path."""

from __future__ import annotations

import pytest

from twinlink.auth.scopes import allows, refusal, twin_of

SCOPE = "twin:rig"


@pytest.mark.parametrize(
    ("method", "path"),
    [
        ("GET", "/api/v1/twins/rig"),
        ("PUT", "/api/v1/twins/rig"),
        ("DELETE", "/api/v1/twins/rig/devices/sensor"),
        ("POST", "/api/v1/twins/rig/processors"),
        ("GET", "/api/v1/twins/rig/history/telemetry"),
        ("GET", "/api/v1/twins/rig/"),
        ("POST", "/twins/rig/services/cad/upload"),
        ("GET", "/api/v1/library"),
        ("HEAD", "/api/v1/library/common/models/beam/versions/latest/files/beam.fmu"),
        ("get", "/api/v1/library/me/data/x"),
    ],
)
def test_a_twins_token_reaches_its_twin_and_library_reads(method: str, path: str) -> None:
    assert allows(SCOPE, method, path)
    assert refusal(SCOPE, (method, path)) is None


@pytest.mark.parametrize(
    ("method", "path"),
    [
        ("GET", "/api/v1/twins"),  # the list of twins is not the twin
        ("GET", "/api/v1/twins/rig2"),
        ("GET", "/api/v1/twins/ri"),
        ("GET", "/api/v1/twins/other/devices"),
        ("GET", "/api/v1/users"),
        ("POST", "/api/v1/tokens"),
        ("GET", "/api/v1/live"),
        ("GET", "/api/v1/runs/3"),
        ("POST", "/api/v1/deployments/rig/runs"),
        ("POST", "/api/v1/library/me/data/x/versions"),
        ("DELETE", "/api/v1/library/common/models/beam"),
        ("GET", "/twins/other/services/cad/"),
        ("GET", "/services/cad/"),  # the default twin's gateway form names no twin
        ("GET", "/api/v1/twins/rig/../../users"),
        ("GET", "/api/v1/twins/rig/./x"),
        ("GET", "/api/v1/twins/rig/.."),
        ("GET", "//api/v1/twins/rig"),
        ("GET", "/api/v1//twins/rig"),
        ("GET", "api/v1/twins/rig"),
        ("GET", "/twins/rig/../other/services/x"),
    ],
)
def test_everything_else_is_refused_naming_the_scope(method: str, path: str) -> None:
    assert not allows(SCOPE, method, path)
    why = refusal(SCOPE, (method, path))
    assert why is not None and "scoped to twin 'rig'" in why and path in why


def test_without_a_request_a_scoped_token_is_refused_and_other_scopes_reach_nothing() -> None:
    assert refusal(SCOPE, None) == "a token scoped to twin 'rig' cannot be used here"
    assert twin_of(SCOPE) == "rig" and twin_of("group:x") is None
    assert not allows("group:x", "GET", "/api/v1/twins/rig")
    assert not allows("twin:", "GET", "/api/v1/twins/")
