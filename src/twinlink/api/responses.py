"""JSON answers for the hot read routes, serialised once with orjson.

A route annotated `-> dict[str, Any]` has FastAPI validate and re-encode the whole answer;
for a search page of nested hits that costs a millisecond or two for nothing.
"""

from __future__ import annotations

from typing import Any

import orjson
from starlette.responses import Response


class JSONAnswer(Response):
    media_type = "application/json"

    def render(self, content: Any) -> bytes:
        return orjson.dumps(content)
