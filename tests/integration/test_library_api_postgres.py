"""tests/integration/test_library_api.py's tests on a server whose store is PostgreSQL."""

from __future__ import annotations

import pytest

from tests.integration import test_library_api
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres_server import database as database
from tests.integration._postgres_server import drop_tests_without_server, server_on_postgres
from tests.integration.test_library_api import library_server

pytestmark = pytest.mark.integration

server = server_on_postgres(library_server)

rerun_on_postgres(test_library_api, globals())
drop_tests_without_server(globals())
