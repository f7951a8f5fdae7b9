"""A cache of values derived from the metadata store, valid while a generation counter stays
the same.

Every change that could alter a cached value bumps the generation after it is written (see
`RegistryService.generation`), and the next lookup finds the cache empty. A value read from the
store is kept only if the generation did not move while it was being read: a read that raced a
change may have seen the old value, and must not outlive the change.

This holds because one server process owns the store; a second process writing to it would
have to tell this one.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Generic, TypeVar

K = TypeVar("K")
V = TypeVar("V")

DEFAULT_LIMIT = 10_000


class GenerationCache(Generic[K, V]):
    def __init__(self, generation: Callable[[], int], limit: int = DEFAULT_LIMIT) -> None:
        self._generation = generation
        self._seen = generation()
        self._values: dict[K, V] = {}
        self.limit = limit

    def _fresh(self) -> dict[K, V]:
        now = self._generation()
        if now != self._seen:
            self._values.clear()
            self._seen = now
        return self._values

    def get(self, key: K) -> V | None:
        """The value of `key` when it is cached and current, else None (so None itself is not
        a value to cache)."""
        return self._fresh().get(key)

    def generation(self) -> int:
        """Take this before reading the store; hand it to `keep`."""
        return self._generation()

    def keep(self, key: K, value: V, read_at: int) -> None:
        """Cache `value`, read from the store when the generation was `read_at`."""
        values = self._fresh()
        if read_at != self._seen:
            return  # something changed during the read: the value may be stale
        if len(values) >= self.limit:
            values.clear()  # crude but bounded; a full cache refills from the store
        values[key] = value

    def clear(self) -> None:
        self._values.clear()

    def __len__(self) -> int:
        return len(self._fresh())
