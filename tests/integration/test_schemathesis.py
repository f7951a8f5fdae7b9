"""schemathesis fuzzes the whole API from its /openapi.json, on a real server: no request
answers a 5xx, and every answer's status, media type and body are as described.

Bounded in time: 8 requests an operation, valid ones and ones that break the schema, the same
ones every run (about 570 requests; 35 to 50 s on a loaded 2-core machine).
test_hostile_numbers.py is the hand-made fuzzer of numbers; this one is generic.

Left out, each for a reason that is not the contract:
- logging out and revoking tokens: a generated id would revoke the token the fuzzer signs in
  with, and every request after it would be a 401;
- the operations that make the server reach out to an address given in the request (a
  gateway service's base URL and its health check, a connector's endpoint): the fuzzer would
  send the server's traffic anywhere. test_openapi_contract.py covers them with addresses on
  this machine.
"""

from __future__ import annotations

from collections import Counter
from typing import Any

import hypothesis
import pytest
import schemathesis
from hypothesis import HealthCheck, Phase
from hypothesis import strategies as st
from schemathesis import GenerationMode
from schemathesis.checks import not_a_server_error
from schemathesis.core.failures import FailureGroup
from schemathesis.schemas import APIOperation, BaseSchema
from schemathesis.specs.openapi.checks import (
    content_type_conformance,
    response_schema_conformance,
    status_code_conformance,
)

from tests.conftest import Server

pytestmark = pytest.mark.integration

EXAMPLES = 8  # requests per operation: valid ones and ones that break the schema
CHECKS = [
    not_a_server_error,
    status_code_conformance,
    content_type_conformance,
    response_schema_conformance,
]
LEFT_OUT = (
    ("POST", r"^/api/v1/auth/logout$"),
    ("DELETE", r"^/api/v1/tokens/\{token_id\}$"),
    (None, r"^/api/v1/twins/\{slug\}/services"),
    (None, r"^/api/v1/twins/\{slug\}/connectors"),
)


def fuzzed(server: Server) -> BaseSchema:
    auth = {"Authorization": f"Bearer {server.admin_token}"}
    schema: BaseSchema = schemathesis.openapi.from_url(f"{server.url}/openapi.json", headers=auth)
    for method, path in LEFT_OUT:
        schema = schema.exclude(method=method, path_regex=path)
    return schema


def fuzz(
    operation: APIOperation[Any, Any, Any, Any], token: str, statuses: Counter[int]
) -> str | None:
    """The first failure of `operation`'s requests (a curl command and what went wrong);
    the status of each answer is counted in `statuses`."""
    failures: list[str] = []
    cases = st.one_of(
        operation.as_strategy(GenerationMode.POSITIVE),
        operation.as_strategy(GenerationMode.NEGATIVE),
    )
    headers = {"Authorization": f"Bearer {token}"}

    @hypothesis.settings(
        max_examples=EXAMPLES,
        deadline=None,
        derandomize=True,  # the same requests every run: a failure is one to reproduce
        phases=[Phase.generate],
        suppress_health_check=list(HealthCheck),
        database=None,
    )
    @hypothesis.given(case=cases)
    def run(case: schemathesis.Case[Any]) -> None:
        if failures:
            return
        try:
            response = case.call_and_validate(headers=headers, checks=CHECKS, timeout=30)
            statuses[response.status_code] += 1
        except (FailureGroup, AssertionError) as err:
            curl = case.as_curl_command(headers={"Authorization": "Bearer $TOKEN"})
            failures.append(f"{operation.label}: {curl}\n{err}")

    run()
    return failures[0] if failures else None


def test_no_request_gets_a_server_error_or_an_answer_not_described(server: Server) -> None:
    failures, tried, statuses = [], 0, Counter[int]()
    for result in fuzzed(server).get_all_operations():
        operation = result.ok()  # type: ignore[union-attr]  # an Err raises here, as wanted
        tried += 1
        failure = fuzz(operation, server.admin_token, statuses)
        if failure is not None:
            failures.append(failure)
    assert not failures, "\n\n".join(failures)
    # The fuzzer reached the handlers (answers of every kind), not only a gate before them.
    assert tried > 60, f"only {tried} operations were fuzzed"
    assert {200, 201, 404, 422} <= set(statuses), statuses
