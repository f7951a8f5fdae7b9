"""Commands to devices (with their log) and device properties (reported, desired, delta)."""

from twinlink.commands.model import CommandRecord
from twinlink.commands.properties import PropertyService
from twinlink.commands.service import CommandService

__all__ = ["CommandRecord", "CommandService", "PropertyService"]
