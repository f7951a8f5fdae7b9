"""Parse YAML into plain data while remembering where each value stood.

PyYAML's safe loader is used with three changes: timestamps stay strings (a DT document's
`createdHuman` must not turn into a datetime that JSON cannot hold), an integer too long for
Python to read is refused with its line, and the composed node tree is walked to map every
path to its line and column, so validation can point at them. The same walk refuses a key
given twice in one mapping: PyYAML would keep the last one without a word.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import yaml

from twinlink.domain.errors import DocumentError, Problem
from twinlink.domain.jsontext import int64_problem

_Base: Any = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

Path = tuple[str | int, ...]


class _IntTooLong(Exception):
    """An integer literal Python will not turn into an int (over 4 300 digits)."""

    # Not a TwinlinkError: control flow inside this module, which answers it as a problem
    # of the document (DocumentError) with the literal's line and column.

    def __init__(self, node: yaml.ScalarNode) -> None:
        super().__init__(node.value)
        self.node = node


class _Loader(_Base):  # type: ignore[misc]
    """SafeLoader without the timestamp resolver."""

    yaml_implicit_resolvers = {  # noqa: RUF012 - overrides PyYAML's class attribute
        first: [(tag, rx) for tag, rx in resolvers if tag != "tag:yaml.org,2002:timestamp"]
        for first, resolvers in _Base.yaml_implicit_resolvers.items()
    }

    def construct_yaml_int(self, node: yaml.ScalarNode) -> int:
        # Such integers are far outside 64 bits anyway; they are refused like one, with their
        # line. YAML 1.1's base 60 (`1:30:00`) is summed part by part, which takes quadratic
        # time for a long one; from 12 parts on (60^12 > 2^63) it is not summed at all.
        if str(node.value).count(":") >= 12:
            raise _IntTooLong(node)
        try:
            return int(super().construct_yaml_int(node))
        except ValueError as err:  # Python reads at most 4 300 digits
            raise _IntTooLong(node) from err


_Loader.add_constructor("tag:yaml.org,2002:int", _Loader.construct_yaml_int)


@dataclass(slots=True)
class SourceDocument:
    """One document of a YAML stream: its data and the position of every path in it."""

    data: Any
    marks: dict[Path, tuple[int, int]] = field(default_factory=dict)
    index: int = 0

    def where(self, path: Path) -> tuple[int, int] | None:
        """Line and column (1-based) of `path`, or of its nearest ancestor that has one."""
        while True:
            if path in self.marks:
                return self.marks[path]
            if not path:
                return None
            path = path[:-1]

    def problem(self, message: str, path: Path = ()) -> Problem:
        pos = self.where(path)
        return Problem(
            message=message,
            path=format_path(path),
            line=pos[0] if pos else None,
            column=pos[1] if pos else None,
            document=self.index,
        )


def format_path(path: Path) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


# Aliases let a small text stand for a huge tree ("billion laughs"); a document is refused
# once its tree holds more values than any real DT document, or nests deeper.
MAX_VALUES = 200_000
MAX_DEPTH = 64


_MERGE = "tag:yaml.org,2002:merge"


class _TooLarge(Exception):
    """A document over MAX_VALUES values or MAX_DEPTH levels, found while walking it."""

    # Not a TwinlinkError: control flow inside this module, which answers it as a problem
    # of the document (DocumentError) with the line where the document starts.


def _position(node: yaml.Node) -> tuple[int, int]:
    return node.start_mark.line + 1, node.start_mark.column + 1


@dataclass(slots=True)
class _Walk:
    """What walking one document's node tree finds: positions and keys given twice."""

    index: int
    marks: dict[Path, tuple[int, int]] = field(default_factory=dict)
    twice: dict[tuple[int, int], Problem] = field(default_factory=dict)

    def record(self, node: yaml.Node, path: Path) -> None:
        if len(self.marks) > MAX_VALUES or len(path) > MAX_DEPTH:
            raise _TooLarge
        self.marks[path] = _position(node)
        if isinstance(node, yaml.MappingNode):
            seen: dict[tuple[str, str], yaml.Node] = {}
            for key_node, value_node in node.value:
                key = (
                    key_node.value if isinstance(key_node, yaml.ScalarNode) else str(key_node.value)
                )
                child = (*path, key)
                self.record(value_node, child)
                # A key's own position is more useful than its value's for "missing"/"unknown".
                self.marks[child] = _position(key_node)
                if isinstance(key_node, yaml.ScalarNode) and key_node.tag != _MERGE:
                    self._once(seen, key_node, child)
        elif isinstance(node, yaml.SequenceNode):
            for i, item in enumerate(node.value):
                self.record(item, (*path, i))

    def _once(self, seen: dict[tuple[str, str], yaml.Node], key: yaml.Node, path: Path) -> None:
        # Keys merged in with `<<` may be overridden (that is what merging is for); two keys
        # written in one mapping may not. The tag tells `1` (a number) from `'1'` (text).
        first = seen.setdefault((key.tag, key.value), key)
        if first is key:
            return
        line, column = _position(key)
        first_line, first_column = _position(first)
        # An alias may show the same mapping again: report each place once, where it is written.
        self.twice.setdefault(
            (line, column),
            Problem(
                f"key {key.value!r} is given twice in one mapping "
                f"(first at line {first_line}, column {first_column}); keep one",
                path=format_path(path),
                line=line,
                column=column,
                document=self.index,
            ),
        )


def parse_yaml_stream(text: str) -> list[SourceDocument]:
    """Parse every document of a YAML stream; a syntax error raises DocumentError
    naming the line."""
    loader = _Loader(text)
    docs: list[SourceDocument] = []
    try:
        while loader.check_node():
            node = loader.get_node()
            if node is not None:
                docs.append(_document(loader, node, len(docs)))
    except yaml.MarkedYAMLError as err:
        raise _syntax_error(err, len(docs)) from err
    except RecursionError:
        # from None: the cause is a thousand frames of the YAML composer, noise to any reader.
        raise DocumentError(
            "The document is too deeply nested; nothing was stored.",
            [Problem(f"more than {MAX_DEPTH} levels", document=len(docs))],
        ) from None
    except yaml.YAMLError as err:
        raise DocumentError(
            "The document is not valid YAML; nothing was stored.", [Problem(message=str(err))]
        ) from err
    finally:
        loader.dispose()
    return docs


def _document(loader: Any, node: yaml.Node, index: int) -> SourceDocument:
    """The stream's document number `index`, composed as `node`: walked first (its size,
    keys given twice, the lines of its values), then built."""
    walk = _Walk(index)
    try:
        walk.record(node, ())
    except _TooLarge as err:
        raise DocumentError(
            "The document is too large or too deeply nested; nothing was stored.",
            [
                Problem(
                    f"more than {MAX_VALUES} values or {MAX_DEPTH} levels "
                    "(YAML aliases expand to copies)",
                    line=node.start_mark.line + 1,
                    column=1,
                    document=index,
                )
            ],
        ) from err
    if walk.twice:
        raise DocumentError(
            "A key is given twice in one mapping; nothing was stored.",
            list(walk.twice.values()),
        )
    data = _construct(loader, node, index)
    return SourceDocument(data=data, marks=walk.marks, index=index)


def _syntax_error(err: yaml.MarkedYAMLError, index: int) -> DocumentError:
    """The problem PyYAML found in document number `index`, with its line and column."""
    mark = err.problem_mark or err.context_mark
    reason = " ".join(x for x in (err.context, err.problem) if x) or "malformed YAML"
    # PyYAML 6.0.4 and later stop deep nesting in the scanner; older ones recurse
    # until RecursionError. Either way the user reads the same headline.
    deep = "nesting depth" in reason
    return DocumentError(
        "The document is too deeply nested; nothing was stored."
        if deep
        else "The document is not valid YAML; nothing was stored.",
        [
            Problem(
                message=reason,
                line=mark.line + 1 if mark else None,
                column=mark.column + 1 if mark else None,
                document=index,
            )
        ],
    )


def _construct(loader: Any, node: yaml.Node, index: int) -> Any:
    try:
        return loader.construct_document(node)
    except _IntTooLong as err:
        line, column = _position(err.node)
        raise DocumentError(
            "The DT document has problems; nothing was stored.",
            [Problem(int64_problem(err.node.value), line=line, column=column, document=index)],
        ) from err


def dump_yaml(data: Any) -> str:
    """Dump plain data as block-style YAML, keys in their original order."""
    return yaml.dump(
        data,
        Dumper=getattr(yaml, "CSafeDumper", yaml.SafeDumper),
        sort_keys=False,
        allow_unicode=True,
        default_flow_style=False,
        width=100,
    )
