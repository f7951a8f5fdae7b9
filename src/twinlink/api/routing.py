"""The route class of the API's routers: JSON request bodies read as every JSON the platform
takes from outside is read (`domain.jsontext`).

FastAPI reads a JSON body with Python's `json`, which takes `NaN` and `1e400` (infinity) and
keeps integers of any size; the handlers then store or forward them with orjson, which cannot
write an integer outside 64 bits: a 500 after the checks had passed. Here a body is parsed with
`jsontext.loads` (standard JSON only, errors with line and column) and an integer outside
64 bits anywhere in it is refused with its place and the one message for it, before any
handler runs.
"""

from __future__ import annotations

from collections.abc import Callable, Coroutine
from typing import Any

from fastapi.routing import APIRoute
from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import Response

from twinlink.domain.jsontext import JsonTextError, first_big_int, int64_problem, loads


class ExactJsonRequest(Request):
    async def json(self) -> Any:
        if not hasattr(self, "_json"):
            try:
                value = loads(await self.body())
            except JsonTextError as err:
                # FastAPI turns any other exception of `json()` into a bare 400.
                raise HTTPException(422, f"The body is not valid JSON: {err}") from err
            found = first_big_int(value)
            if found is not None:
                path, number = found
                raise HTTPException(422, f"body.{path}: {int64_problem(number)}" if path else
                                    f"body: {int64_problem(number)}")  # fmt: skip
            self._json = value
        return self._json


class ExactJsonRoute(APIRoute):
    """`APIRouter(route_class=ExactJsonRoute)`: its routes' JSON bodies are read exactly."""

    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        handler = super().get_route_handler()

        async def exact_json_handler(request: Request) -> Response:
            return await handler(ExactJsonRequest(request.scope, request.receive))

        return exact_json_handler
