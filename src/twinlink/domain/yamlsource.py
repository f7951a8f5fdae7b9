"""Parse YAML into plain data while remembering where each value stood.

PyYAML's safe loader is used with two changes: timestamps stay strings (a DT document's
`createdHuman` must not turn into a datetime that JSON cannot hold), and the composed node
tree is walked to map every path to its line and column, so validation can point at them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import yaml

from twinlink.domain.errors import DocumentError, Problem

_Base: Any = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

Path = tuple[str | int, ...]


class _Loader(_Base):  # type: ignore[misc]
    """SafeLoader without the timestamp resolver."""

    yaml_implicit_resolvers = {  # noqa: RUF012 - overrides PyYAML's class attribute
        first: [(tag, rx) for tag, rx in resolvers if tag != "tag:yaml.org,2002:timestamp"]
        for first, resolvers in _Base.yaml_implicit_resolvers.items()
    }


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


class _TooLarge(Exception):
    pass


def _record(node: yaml.Node, path: Path, marks: dict[Path, tuple[int, int]]) -> None:
    if len(marks) > MAX_VALUES or len(path) > MAX_DEPTH:
        raise _TooLarge
    marks[path] = (node.start_mark.line + 1, node.start_mark.column + 1)
    if isinstance(node, yaml.MappingNode):
        for key_node, value_node in node.value:
            key = key_node.value if isinstance(key_node, yaml.ScalarNode) else str(key_node.value)
            child = (*path, key)
            _record(value_node, child, marks)
            # A key's own position is more useful than its value's for "missing"/"unknown".
            marks[child] = (key_node.start_mark.line + 1, key_node.start_mark.column + 1)
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            _record(item, (*path, i), marks)


def parse_yaml_stream(text: str) -> list[SourceDocument]:
    """Parse every document of a YAML stream; a syntax error raises DocumentError
    naming the line."""
    loader = _Loader(text)
    docs: list[SourceDocument] = []
    try:
        while loader.check_node():
            node = loader.get_node()
            if node is None:
                continue
            marks: dict[Path, tuple[int, int]] = {}
            try:
                _record(node, (), marks)
            except _TooLarge:
                raise DocumentError(
                    "The document is too large or too deeply nested; nothing was stored.",
                    [
                        Problem(
                            f"more than {MAX_VALUES} values or {MAX_DEPTH} levels "
                            "(YAML aliases expand to copies)",
                            line=node.start_mark.line + 1,
                            column=1,
                            document=len(docs),
                        )
                    ],
                ) from None
            data = loader.construct_document(node)
            docs.append(SourceDocument(data=data, marks=marks, index=len(docs)))
    except yaml.MarkedYAMLError as err:
        mark = err.problem_mark or err.context_mark
        reason = " ".join(x for x in (err.context, err.problem) if x) or "malformed YAML"
        # PyYAML 6.0.4 and later stop deep nesting in the scanner; older ones recurse
        # until RecursionError below. Either way the user reads the same headline.
        deep = "nesting depth" in reason
        raise DocumentError(
            "The document is too deeply nested; nothing was stored."
            if deep
            else "The document is not valid YAML; nothing was stored.",
            [
                Problem(
                    message=reason,
                    line=mark.line + 1 if mark else None,
                    column=mark.column + 1 if mark else None,
                    document=len(docs),
                )
            ],
        ) from err
    except RecursionError:
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
