"""Numbered query arguments ($1, $2, ...) collected as a query is put together."""

from __future__ import annotations


class Args(list[object]):
    """The arguments of one query; calling it with a value adds it and gives its marker."""

    def __call__(self, value: object) -> str:
        self.append(value)
        return f"${len(self)}"


def like_escaped(text: str) -> str:
    """`text` matched literally inside a LIKE pattern (ESCAPE '\\')."""
    return text.replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_")
