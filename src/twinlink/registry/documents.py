"""Reading request bodies into documents, and grouping documents into twins."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from twinlink.domain.document import DocumentPart, validate_part
from twinlink.domain.errors import DocumentError, DocumentTooLargeError, Problem
from twinlink.domain.jsontext import JsonTextError, loads, loads_document
from twinlink.domain.slug import slug_for
from twinlink.domain.yamlsource import MAX_DEPTH, SourceDocument, parse_yaml_stream

REFUSED = "The DT document has problems; nothing was stored."


@dataclass(slots=True)
class TwinParts:
    """The parts of one twin found in one request, by privacy level."""

    key: str
    parts: dict[str, tuple[DocumentPart, dict[str, Any], SourceDocument]]

    @property
    def first(self) -> tuple[DocumentPart, dict[str, Any], SourceDocument]:
        return next(iter(self.parts.values()))

    @property
    def global_id(self) -> str | None:
        return next((p.global_id for p, _, _ in self.parts.values() if p.global_id), None)

    @property
    def explicit_slug(self) -> str | None:
        return next((str(r["slug"]) for _, r, _ in self.parts.values() if r.get("slug")), None)


def parse_documents(body: bytes, content_type: str, max_bytes: int) -> list[SourceDocument]:
    """YAML (one or many documents) or JSON (an object or a list of objects)."""
    if len(body) > max_bytes:
        raise DocumentTooLargeError(
            f"The document is larger than the limit of {max_bytes} bytes"
            " (TWINLINK_MAX_DOCUMENT_BYTES)."
        )
    try:
        text = body.decode("utf-8")
    except UnicodeDecodeError as err:
        raise DocumentError("The document is not UTF-8 text.", [Problem(str(err))]) from err
    if "json" in content_type:
        return _json_documents(body, text)
    docs = parse_yaml_stream(text)
    if not docs:
        raise DocumentError(
            "The request holds no document.", [Problem("empty body", line=1, column=1)]
        )
    return docs


def _json_documents(body: bytes, text: str) -> list[SourceDocument]:
    try:
        # Integers stay exact and a key given twice is refused, as in YAML documents.
        data = loads_document(body)
    except JsonTextError as err:
        raise DocumentError(
            REFUSED
            if _readable_json(body)
            else "The document is not valid JSON; nothing was stored.",
            [Problem(err.reason, line=err.line, column=err.column)],
        ) from err
    except RecursionError as err:  # msgspec stops at Python's recursion limit (about 1 000 levels)
        raise DocumentError(
            "The document is too deeply nested; nothing was stored.",
            [Problem(f"more than {MAX_DEPTH} levels")],
        ) from err
    if isinstance(data, dict):
        try:
            # JSON is YAML: parsing it again gives the line and column of every value.
            return [SourceDocument(data, parse_yaml_stream(text)[0].marks, 0)]
        except (DocumentError, IndexError):
            return [SourceDocument(data, {}, 0)]
    if isinstance(data, list) and data:
        return [SourceDocument(item, {}, i) for i, item in enumerate(data)]
    raise DocumentError(REFUSED, [Problem("expected an object or a non-empty list of objects")])


def _readable_json(body: bytes) -> bool:
    """Whether the text is JSON at all (the error is then in what it says, not its syntax)."""
    try:
        loads(body)
    except (JsonTextError, RecursionError):
        return False
    return True


def group_by_twin(docs: list[SourceDocument], slug: str | None) -> list[TwinParts]:
    """Validate every document (all problems at once) and group the parts by twin."""
    problems: list[Problem] = []
    groups: dict[str, TwinParts] = {}
    for source in docs:
        try:
            part, raw = validate_part(source)
        except DocumentError as err:
            problems.extend(err.problems)
            continue
        key = (
            part.global_id
            or slug
            or raw.get("slug")
            or slug_for(None, part.hosting_iri, None, part.name)
        )
        if not key:
            problems.append(
                source.problem("the twin has no `id`/`dt-id` and no name to derive its slug from")
            )
            continue
        group = groups.setdefault(str(key), TwinParts(str(key), {}))
        if part.privacy in group.parts:
            problems.append(
                source.problem(
                    f"a second {part.privacy!r} part for the same twin in one request", ("privacy",)
                )
            )
            continue
        group.parts[part.privacy] = (part, raw, source)
    if problems:
        raise DocumentError(REFUSED, problems)
    if slug is not None and len(groups) > 1:
        raise DocumentError("A request for one twin holds documents of several twins.")
    return list(groups.values())
