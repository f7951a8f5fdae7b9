"""The server tests of tests/integration/test_gateway_access.py on a `twinlink up` server whose
store is PostgreSQL (_postgres_server.py)."""

from __future__ import annotations

import pytest

from tests.integration import test_gateway_access
from tests.integration._gateway import gateway_server
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres_server import database as database
from tests.integration._postgres_server import drop_tests_without_server, server_on_postgres

pytestmark = pytest.mark.integration

server = server_on_postgres(gateway_server)

rerun_on_postgres(test_gateway_access, globals())
drop_tests_without_server(globals())
