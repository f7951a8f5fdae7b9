"""The Ilmatar overhead crane's example services, the systems the Data Link paper linked:
a historian with a custom login, an OPC UA server with an HTTP bridge over it, a CAD file
server and an OAuth 2.0 sensor manager, all driven by one simulated crane (docs/crane.md)."""

from twinlink.crane.runner import Crane, start_crane
from twinlink.crane.settings import CranePorts, CraneSettings, DemoCredentials

__all__ = ["Crane", "CranePorts", "CraneSettings", "DemoCredentials", "start_crane"]
