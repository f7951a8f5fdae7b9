"""The API description (/openapi.json) as clients read it, and a way to write it without a
server: `python -m twinlink.api.contract [FILE]` (the web app's types are generated from it,
`make ui-types`).

FastAPI describes every answer from the routes' models. Two things it cannot know are set
here: error answers are `application/problem+json` (RFC 9457), not `application/json`; and a
request that is not valid is a 422 problem too (problems.py), not FastAPI's own
`HTTPValidationError`, which this API never sends.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path
from typing import Any

from fastapi import FastAPI
from fastapi.openapi.utils import get_openapi

from twinlink.api.models.problem import MEANINGS
from twinlink.api.problems import PROBLEM

_PROBLEM_REF = {"$ref": "#/components/schemas/Problem"}
_FASTAPI_ONLY = ("HTTPValidationError", "ValidationError")


def describe(app: FastAPI) -> dict[str, Any]:
    """The app's OpenAPI document, errors as problem details; built once per app."""
    if app.openapi_schema is None:
        spec = get_openapi(
            title=app.title,
            version=app.version,
            openapi_version=app.openapi_version,
            description=app.description,
            routes=app.routes,
        )
        for path in spec.get("paths", {}).values():
            for operation in path.values():
                _errors_as_problems(operation.get("responses", {}))
        schemas = spec.get("components", {}).get("schemas", {})
        for name in _FASTAPI_ONLY:
            schemas.pop(name, None)
        app.openapi_schema = spec
    return app.openapi_schema


def _errors_as_problems(responses: dict[str, Any]) -> None:
    for status, response in responses.items():
        if not status.isdigit() or int(status) < 400:
            continue
        response["content"] = {PROBLEM: {"schema": _PROBLEM_REF}}
        if int(status) == 422:
            response["description"] = MEANINGS[422]


def write(path: Path | None) -> None:
    """Write the description of an app built with default settings in a scratch data dir;
    nothing is started (no lifespan), so no server, port or store is needed."""
    from twinlink.app import create_app
    from twinlink.config import Settings

    with tempfile.TemporaryDirectory() as scratch:
        spec = describe(create_app(Settings(data_dir=Path(scratch))))
    text = json.dumps(spec, indent=2, sort_keys=False) + "\n"
    if path is None:
        sys.stdout.write(text)
    else:
        path.write_text(text, encoding="utf-8")


if __name__ == "__main__":
    write(Path(sys.argv[1]) if len(sys.argv) > 1 else None)
