"""Request dependencies: the services, and who the caller is."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import Depends, Request
from fastapi.security import HTTPAuthorizationCredentials, HTTPBearer

from twinlink.auth.rights import ANONYMOUS, Principal
from twinlink.auth.service import AuthError, AuthService
from twinlink.domain.errors import ForbiddenError
from twinlink.registry.service import RegistryService
from twinlink.search import SearchService

_bearer = HTTPBearer(auto_error=False, description="An API token: `Authorization: Bearer tl_...`")


def services(request: Request) -> Any:
    return request.app.state.services


Bearer = Annotated[HTTPAuthorizationCredentials | None, Depends(_bearer)]


async def optional_principal(request: Request, credentials: Bearer) -> Principal:
    """The caller, or ANONYMOUS when no token is sent. A token that is sent must be valid."""
    if credentials is None:
        if request.headers.get("authorization"):
            raise AuthError("the Authorization header must be 'Bearer <token>'")
        return ANONYMOUS
    auth: AuthService = request.app.state.services.auth
    # A scoped token (a run's) is checked against the request's path (auth/scopes.py).
    return await auth.authenticate(credentials.credentials, (request.method, request.url.path))


async def principal(
    caller: Annotated[Principal, Depends(optional_principal)],
) -> Principal:
    if caller.user is None:
        raise AuthError("a token is required")
    return caller


async def admin(caller: Annotated[Principal, Depends(principal)]) -> Principal:
    if not caller.is_admin:
        raise ForbiddenError("this needs a platform admin")
    return caller


def registry(request: Request) -> RegistryService:
    return request.app.state.services.registry  # type: ignore[no-any-return]


def auth_service(request: Request) -> AuthService:
    return request.app.state.services.auth  # type: ignore[no-any-return]


def search_service(request: Request) -> SearchService:
    return request.app.state.services.search  # type: ignore[no-any-return]


Caller = Annotated[Principal, Depends(principal)]
MaybeCaller = Annotated[Principal, Depends(optional_principal)]
Admin = Annotated[Principal, Depends(admin)]
Registry = Annotated[RegistryService, Depends(registry)]
Auth = Annotated[AuthService, Depends(auth_service)]
Search = Annotated[SearchService, Depends(search_service)]
