"""Reading DT documents from request bodies (YAML or JSON)."""

from __future__ import annotations

from typing import Any

from fastapi import Request

from twinlink.domain.yamlsource import SourceDocument
from twinlink.registry.documents import parse_documents

DOCUMENT_BODY: dict[str, Any] = {
    "requestBody": {
        "required": True,
        "description": "A DT document, or several (a YAML stream with `---`, or a JSON list): "
        "the parts of one twin split by privacy, or several twins.",
        "content": {
            "application/yaml": {"schema": {"type": "string"}},
            "application/json": {"schema": {"type": "object", "additionalProperties": True}},
        },
    }
}


async def read_documents(request: Request) -> list[SourceDocument]:
    limit: int = request.app.state.settings.max_document_bytes
    declared = request.headers.get("content-length")
    if declared and declared.isdigit() and int(declared) > limit:
        return parse_documents(b"x" * (limit + 1), "", limit)  # raises the size problem
    body = await request.body()
    return parse_documents(body, request.headers.get("content-type", ""), limit)
