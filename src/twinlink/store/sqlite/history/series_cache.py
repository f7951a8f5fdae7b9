"""The writer's memory of the series table, kept in step with what is committed.

A group commit is one transaction with a savepoint per item. What an item adds (a new
series id, a wider span, a forgotten twin, a series with small blocks) is staged in a layer
of its own: released into the round's layer when the item's savepoint is, kept for good only
when the round commits, and thrown away with a savepoint or a transaction that fails. A
series id that was never committed is therefore never handed out again (a disk that fills up
at COMMIT once made a new signal take over the id of one that was rolled back).
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable
from dataclasses import dataclass, field
from typing import TypeVar

Key = tuple[int, str, str]  # (twin id, stream, signal)
Entry = tuple[int, int]  # (series id, widest block in ns)
StreamKey = tuple[int, str]
K = TypeVar("K", bound=Hashable)


@dataclass(slots=True)
class _Layer:
    entries: dict[Key, Entry | None] = field(default_factory=dict)  # None: forgotten
    signals: dict[StreamKey, int] = field(default_factory=dict)  # change of signals a stream
    small: set[int] = field(default_factory=set)  # series ids that got small blocks
    staged: dict[int, int] = field(default_factory=dict)  # change of staged rows a twin


class SeriesCache:
    def __init__(self) -> None:
        self._committed: dict[Key, Entry] = {}
        self._signals: dict[StreamKey, int] = {}
        self._small: set[int] = set()
        self._staged: dict[int, int] = {}  # twin id -> rows in `staged` (staging.py)
        self._staged_total = 0
        self.hot: set[int] = set()  # twins with at least `hot_rows` staged rows
        self.hot_rows = 5_000
        self._layers: list[_Layer] = []

    def load(self, rows: Iterable[tuple[int, int, str, str, int]], staged: dict[int, int]) -> None:
        """Replace everything with (id, twin id, stream, signal, span) rows of `series` and
        the staged rows per twin."""
        self._committed.clear()
        self._signals.clear()
        self._layers.clear()
        self._staged = {twin: n for twin, n in staged.items() if n}
        self._staged_total = sum(self._staged.values())
        for sid, twin_id, stream, signal, span in rows:
            self._committed[(twin_id, stream, signal)] = (sid, span)
            self._signals[(twin_id, stream)] = self._signals.get((twin_id, stream), 0) + 1

    # -- transactions ----------------------------------------------------------------------

    def begin(self) -> None:
        """A round (the first layer) or an item within it."""
        self._layers.append(_Layer())

    def release(self) -> None:
        """The innermost layer holds: into the one below it, or for good when it is the
        round (call after COMMIT succeeded)."""
        top = self._layers.pop()
        if self._layers:
            below = self._layers[-1]
            below.entries.update(top.entries)
            _add_counts(below.signals, top.signals)
            below.small |= top.small
            _add_counts(below.staged, top.staged)
            return
        for key, entry in top.entries.items():
            if entry is None:
                self._committed.pop(key, None)
            else:
                self._committed[key] = entry
        _add_counts(self._signals, top.signals)
        self._small |= top.small
        _add_counts(self._staged, top.staged)
        self._staged_total += sum(top.staged.values())
        for twin_id in top.staged:
            if self._staged.get(twin_id, 0) >= self.hot_rows:
                self.hot.add(twin_id)
            else:
                self.hot.discard(twin_id)

    def rollback(self) -> None:
        """Forget what the innermost layer staged."""
        self._layers.pop()

    def abandon(self) -> None:
        """The round failed: forget everything staged in it."""
        self._layers.clear()

    # -- reads and changes (inside a layer) ------------------------------------------------

    def get(self, key: Key) -> Entry | None:
        for layer in reversed(self._layers):
            entries = layer.entries
            if entries and key in entries:  # most rounds stage no series at all
                return entries[key]
        return self._committed.get(key)

    def signals(self, twin_id: int, stream: str) -> int:
        """How many signals the stream has, counting those staged."""
        key = (twin_id, stream)
        return self._signals.get(key, 0) + sum(layer.signals.get(key, 0) for layer in self._layers)

    def add(self, key: Key, series_id: int, span: int) -> None:
        """A series just inserted."""
        top = self._layers[-1]
        top.entries[key] = (series_id, span)
        stream = (key[0], key[1])
        top.signals[stream] = top.signals.get(stream, 0) + 1

    def widen(self, key: Key, series_id: int, span: int) -> None:
        self._layers[-1].entries[key] = (series_id, span)

    def forget_twin(self, twin_id: int) -> None:
        """The twin's series were deleted (in this transaction)."""
        keys = {k for k in self._committed if k[0] == twin_id}
        for layer in self._layers:
            keys.update(k for k in layer.entries if k[0] == twin_id)
        top = self._layers[-1]
        for key in keys:
            if self.get(key) is not None:
                top.entries[key] = None
                stream = (key[0], key[1])
                top.signals[stream] = top.signals.get(stream, 0) - 1

    def note_staged(self, twin_id: int, rows: int) -> None:
        """Rows of `staged` added (or, negative, moved into blocks) for a twin."""
        top = self._layers[-1].staged
        top[twin_id] = top.get(twin_id, 0) + rows

    def staged(self, twin_id: int | None = None) -> int:
        """Committed staged rows of a twin (of all twins when None). Safe to call from
        another thread than the writer's: it reads one committed dict."""
        return self._staged_total if twin_id is None else self._staged.get(twin_id, 0)

    def staged_twins(self, rows: int) -> list[int]:
        """Twins with staged rows, as many as hold about `rows` of them (at least one); the
        writer's thread only."""
        picked: list[int] = []
        total = 0
        for twin_id, count in self._staged.items():
            if picked and total + count > rows:
                break
            picked.append(twin_id)
            total += count
        return picked

    def staged_now(self, twin_id: int) -> int:
        """Staged rows of a twin counting those of the open round (writer thread only)."""
        return self._staged.get(twin_id, 0) + sum(
            layer.staged.get(twin_id, 0) for layer in self._layers
        )

    def note_small(self, series_id: int) -> None:
        self._layers[-1].small.add(series_id)

    def take_small(self) -> set[int]:
        """The committed series that got small blocks since the last call."""
        taken, self._small = self._small, set()
        return taken


def _add_counts(into: dict[K, int], changes: dict[K, int]) -> None:
    for key, change in changes.items():
        total = into.get(key, 0) + change
        if total:
            into[key] = total
        else:
            into.pop(key, None)
