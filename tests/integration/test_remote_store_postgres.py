"""tests/unit/test_remote_store.py's tests on PostgreSQL."""

from __future__ import annotations

import pytest

from tests.integration._postgres import postgres_cluster as postgres_cluster
from tests.integration._postgres import postgres_dsn as postgres_dsn
from tests.integration._postgres import rerun_on_postgres
from tests.integration._postgres import stores as stores
from tests.unit import test_remote_store

pytestmark = pytest.mark.integration

rerun_on_postgres(test_remote_store, globals())
