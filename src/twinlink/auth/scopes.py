"""Scoped tokens: what a token limited to one twin (a lifecycle run's, `twin:<slug>`) may
reach. Checked in one place, when the token is authenticated for a request
(AuthService.authenticate): a token with a scope used where no request path is known (the
live WebSocket, which names twins in its messages) is refused too.

A twin's token may use, with its user's rights:
- `/api/v1/twins/<slug>` and everything below it (document, devices, history, commands,
  processors, connectors, services...);
- `/twins/<slug>/...`, the twin's gateway;
- reads (GET, HEAD) of `/api/v1/library...`, to fetch assets.
Paths with empty, `.` or `..` segments are refused outright, so no spelling of another path
passes as the twin's.
"""

from __future__ import annotations

from twinlink.domain.runs import TWIN_SCOPE

_READS = frozenset({"GET", "HEAD"})


def twin_of(scope: str) -> str | None:
    """The twin a scope names (None: a scope of another kind)."""
    return scope[len(TWIN_SCOPE) :] if scope.startswith(TWIN_SCOPE) else None


def allows(scope: str, method: str, path: str) -> bool:
    twin = twin_of(scope)
    if not twin:
        return False
    segments = path.split("/")[1:]
    inner = segments[:-1]  # a trailing slash makes an empty last segment, which is harmless
    if not path.startswith("/") or any(s in ("", ".", "..") for s in inner):
        return False
    if segments and segments[-1] in (".", ".."):
        return False
    if segments[:4] == ["api", "v1", "twins", twin] or segments[:2] == ["twins", twin]:
        return True
    return method.upper() in _READS and segments[:3] == ["api", "v1", "library"]


def refusal(scope: str, request: tuple[str, str] | None) -> str | None:
    """Why a token of `scope` may not make `request` (method, path); None when it may."""
    twin = twin_of(scope) or scope
    if request is None:
        return f"a token scoped to twin {twin!r} cannot be used here"
    method, path = request
    if allows(scope, method, path):
        return None
    return (
        f"this token is scoped to twin {twin!r}: it may use /api/v1/twins/{twin}/..., "
        f"/twins/{twin}/... and read /api/v1/library, not {method} {path}"
    )
