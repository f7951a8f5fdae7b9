"""`${...}` in a twin package: its strings filled from the deployment's parameters, names
and assets.

A string that is exactly one `${...}` takes the value's type (`"${params.zeta}"` is the number
0.7, not the text); inside longer text the value is written in (numbers as JSON writes them).
`$${` is a literal `${`. Every unknown variable is reported with where it stands, not only
the first: a package author fixes them all in one go.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

import orjson

from twinlink.domain.errors import DocumentError, Problem
from twinlink.domain.yamlsource import Path, SourceDocument, format_path

_TOKEN = re.compile(r"\$\$\{|\$\{([^}]*)\}|\$\{")
_WHOLE = re.compile(r"^\$\{([^}]*)\}$")
REFUSED = "The twin package's templates name what is not there; nothing was deployed."


class Variables:
    """What `${...}` may name: `params.NAME` (nested objects by more dots), `deployment.name`,
    `twin.slug`, `twin.url`, `server.url` and `assets.ALIAS`."""

    def __init__(self, params: Mapping[str, Any], flat: Mapping[str, Any]) -> None:
        self.params = params
        self.flat = flat

    def lookup(self, name: str) -> tuple[bool, Any]:
        if name in self.flat:
            return True, self.flat[name]
        head, _, rest = name.partition(".")
        if head != "params" or not rest:
            return False, None
        value: Any = self.params
        for part in rest.split("."):
            if not isinstance(value, Mapping) or part not in value:
                return False, None
            value = value[part]
        return True, value

    def known(self) -> list[str]:
        return sorted({*self.flat, *(f"params.{p}" for p in self.params)})


class Renderer:
    """Fills in the strings of one file's values; `problems` gathers what could not be."""

    def __init__(self, variables: Variables, source: SourceDocument | None, file: str) -> None:
        self.variables = variables
        self.source = source
        self.file = file
        self.problems: list[Problem] = []

    def render(self, value: Any, path: Path = ()) -> Any:
        if isinstance(value, str):
            return self._string(value, path)
        if isinstance(value, dict):
            return {k: self.render(v, (*path, k)) for k, v in value.items()}
        if isinstance(value, list):
            return [self.render(v, (*path, i)) for i, v in enumerate(value)]
        return value

    def _string(self, text: str, path: Path) -> Any:
        if "${" not in text:
            return text
        whole = _WHOLE.match(text)
        if whole:
            return self._value(whole.group(1), path, text)

        def fill(match: re.Match[str]) -> str:
            token = match.group(0)
            if token == "$${":
                return "${"
            if match.group(1) is None:
                self._problem("`${` without a closing `}` (write `$${` for a literal `${`)", path)
                return token
            value = self._value(match.group(1), path, token)
            return value if isinstance(value, str) else orjson.dumps(value).decode()

        return _TOKEN.sub(fill, text)

    def _value(self, name: str, path: Path, token: str) -> Any:
        found, value = self.variables.lookup(name.strip())
        if not found:
            known = ", ".join(self.variables.known())
            self._problem(f"unknown variable {token}; known: {known}", path)
            return token
        return value

    def _problem(self, message: str, path: Path) -> None:
        if self.source is not None:
            problem = self.source.problem(message, path)
        else:
            problem = Problem(message, format_path(path))
        if self.file:
            problem = Problem(f"{self.file}: {problem.message}", problem.path, problem.line,
                              problem.column)  # fmt: skip
        self.problems.append(problem)


def render_all(renderers: list[Renderer]) -> None:
    """Raise one DocumentError for every problem the renderers found, if any."""
    problems = [p for r in renderers for p in r.problems]
    if problems:
        raise DocumentError(REFUSED, problems)
