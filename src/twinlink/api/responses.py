"""JSON answers for the hot read routes, serialised once with orjson.

A route annotated `-> dict[str, Any]` has FastAPI validate and re-encode the whole answer;
for a search page of nested hits that costs a millisecond or two for nothing. Such a route
names its model (`response_model=`) for /openapi.json only: a handler that returns a
`JSONAnswer` is sent as it is.
"""

from __future__ import annotations

from typing import Any

import orjson
from starlette.responses import JSONResponse


class JSONAnswer(JSONResponse):
    # A JSONResponse, so FastAPI describes the route's answer by its response model (for any
    # other response class it writes `{"type": "string"}`).
    media_type = "application/json"

    def render(self, content: Any) -> bytes:
        return orjson.dumps(content)
