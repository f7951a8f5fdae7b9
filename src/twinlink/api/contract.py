"""The API description (/openapi.json) as clients read it (`python -m twinlink.openapi [FILE]`
writes it without a server; the web app's types are generated from it, `make ui-types`).

FastAPI describes every answer from the routes' models. Two things it cannot know are set
here: error answers are `application/problem+json` (RFC 9457), not `application/json`; and a
request that is not valid is a 422 problem too (problems.py), not FastAPI's own
`HTTPValidationError`, which this API never sends.
"""

from __future__ import annotations

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
