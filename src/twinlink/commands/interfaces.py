"""The command and property rules of each twin, read from its merged `interface` and cached
until the registry changes (the same pattern as ingest's signal rules)."""

from __future__ import annotations

from twinlink.commands.rules import Rules, rules_from_interface
from twinlink.domain.merge import merge_parts
from twinlink.registry.cache import GenerationCache
from twinlink.registry.service import RegistryService


class InterfaceRules:
    def __init__(self, registry: RegistryService) -> None:
        self.registry = registry
        self._rules: GenerationCache[int, Rules] = GenerationCache(lambda: registry.generation)

    async def get(self, twin_id: int) -> Rules:
        rules = self._rules.get(twin_id)
        if rules is None:
            read_at = self._rules.generation()
            parts = await self.registry.store.get_parts(twin_id)
            rules = rules_from_interface(merge_parts(parts).get("interface") if parts else None)
            self._rules.keep(twin_id, rules, read_at)
        return rules
