"""tests/integration/test_deployments.py's tests on a server whose store is PostgreSQL."""

from __future__ import annotations

import pytest

from tests.integration import test_deployments
from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres_server import database as database
from tests.integration._postgres_server import drop_tests_without_server
from tests.integration._postgres_server import server as server

pytestmark = pytest.mark.integration

rerun_on_postgres(test_deployments, globals())
drop_tests_without_server(globals())
