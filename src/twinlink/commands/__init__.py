"""Commands to devices (with their log) and device properties (reported, desired, delta)."""

from twinlink.commands.properties import PropertyService
from twinlink.commands.service import CommandService
from twinlink.domain.commands import CommandRecord

__all__ = ["CommandRecord", "CommandService", "PropertyService"]
