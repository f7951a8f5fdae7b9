"""The Ilmatar overhead crane's example services, the systems the Data Link paper linked:
a historian with a custom login, an OPC UA server with an HTTP bridge over it, a CAD file
server and an OAuth 2.0 sensor manager, all driven by one simulated crane (docs/crane.md).

They stand in for systems made by others, so nothing here imports twinlink: how twinlink's
gateway signs in to them is the demo's business (examples/demo, twinlink_demo.crane_gateway).
The DT documents that describe them are beside this package, in examples/ilmatar/."""

from ilmatar_crane.runner import Crane, start_crane
from ilmatar_crane.settings import CranePorts, CraneSettings, DemoCredentials

__all__ = ["Crane", "CranePorts", "CraneSettings", "DemoCredentials", "start_crane"]
