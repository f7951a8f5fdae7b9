"""The history tests of tests/unit/test_history_service.py that any backend must pass, on
PostgreSQL, against a real server (_postgres.py)."""

from __future__ import annotations

import pytest

from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres import stores as stores
from tests.unit import test_history_service

rerun_on_postgres(test_history_service, globals())

# The cluster starts before the module's first test, which the hygiene check then counts.
pytestmark = [pytest.mark.integration, pytest.mark.usefixtures("postgres_cluster")]
