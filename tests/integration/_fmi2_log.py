"""An FMI 2.0 logger callback for tests that collects what an FMU logs."""

from __future__ import annotations

import fmpy
from fmpy.fmi2 import (
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)


class Fmi2Log:
    """fmi2 callbacks whose logger collects (status, category, message).

    Deliberately without fmpy.logging.addLoggerProxy: that proxy keeps ONE global slot for the
    Python logger, so the last call wins for every FMU in the process and the callback would have
    to outlive them all. These FMUs format their messages themselves, so none is needed.
    """

    def __init__(self) -> None:
        self.messages: list[tuple[int, str, str]] = []
        self.logger = fmi2CallbackLoggerTYPE(self._log)
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.logger = self.logger
        self.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(fmpy.calloc)
        self.callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(fmpy.free)

    def _log(
        self, env: object, instance: bytes, status: int, category: bytes, message: bytes
    ) -> None:
        self.messages.append((status, category.decode(), message.decode()))

    def text(self) -> str:
        return "\n".join(message for _, _, message in self.messages)
