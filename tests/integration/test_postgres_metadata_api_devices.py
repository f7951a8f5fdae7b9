"""The server tests of tests/integration/test_devices.py on a `twinlink up` server whose
store is PostgreSQL (_postgres_server.py)."""

from __future__ import annotations

import pytest

from tests.integration import test_devices
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres_server import database as database
from tests.integration._postgres_server import drop_tests_without_server
from tests.integration._postgres_server import server as server

pytestmark = pytest.mark.integration

rerun_on_postgres(test_devices, globals())
drop_tests_without_server(globals())
