"""A processor's diagnostics survive: stopping it keeps its logs and last error, and an FMU
that fails to instantiate is shown with its own log lines, even at the default log_level."""

from __future__ import annotations

from typing import Any

import pytest

from tests.conftest import FmuFiles, Server
from tests.integration._live import device_twin
from tests.integration._processors import create, events, post, processor, wait_for
from tests.integration._processors import server as server  # module fixture
from tests.integration.test_fmu_processors import upload

pytestmark = pytest.mark.integration


def logs(server: Server, slug: str, name: str) -> list[str]:
    with server.admin as admin:
        r = admin.get(f"/api/v1/twins/{slug}/processors/{name}/logs")
    assert r.status_code == 200, r.text
    return [line["text"] for line in r.json()["lines"]]


def act(server: Server, slug: str, name: str, action: str) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors/{name}/{action}")
    assert r.status_code == 200, r.text
    return r.json()  # type: ignore[no-any-return]


def test_stopping_a_processor_keeps_its_logs_and_last_error(
    server: Server, fmu_files: FmuFiles
) -> None:
    slug, [device] = device_twin(server)
    upload(server, slug, fmu_files("status"), "status.fmu")
    create(server, slug, name="strict", blueprint="fmu", inputs={"u": "x"},
           params={"fmu": "status.fmu"})  # fmt: skip
    wait_for(server, slug, "strict", lambda p: p["state"] == "running")
    post(server, device, 1, [{"x": 1.0}, {"x": -2.0}])  # fmi2Error: the worker fails
    failed = wait_for(server, slug, "strict", lambda p: p["stats"]["restarts"] >= 1)
    assert "negative input u=-2" in failed["last_error"]
    before = logs(server, slug, "strict")
    assert any("negative input u=-2" in line for line in before), before

    stopped = act(server, slug, "strict", "stop")
    assert stopped["state"] == "stopped" and stopped["last_error"] == failed["last_error"]
    assert processor(server, slug, "strict")["last_error"] == failed["last_error"]
    kept = logs(server, slug, "strict")
    assert kept[: len(before)] == before  # the lines up to the failure, in order

    # Started again, the earlier lines stay in front of the new worker's.
    act(server, slug, "strict", "start")
    wait_for(server, slug, "strict", lambda p: p["state"] == "running")
    assert logs(server, slug, "strict")[: len(before)] == before


def test_an_fmus_own_words_at_instantiation_are_shown_at_the_default_log_level(
    server: Server, fmu_files: FmuFiles
) -> None:
    slug, _ = device_twin(server)
    upload(server, slug, fmu_files("status"), "status.fmu")
    # The status FMU refuses instances named refuse*, saying why only at its info level.
    create(server, slug, name="refuse-me", blueprint="fmu", inputs={"u": "x"},
           params={"fmu": "status.fmu"})  # fmt: skip
    view = wait_for(server, slug, "refuse-me", lambda p: p["stats"]["restarts"] >= 1)
    assert "cannot import module 'twinlink_missing_module'" in view["last_error"], view
    assert "(no log message)" not in view["last_error"]
    [event, *_] = events(server, slug, "refuse-me", "failed")
    assert "twinlink_missing_module" in event["message"]
    lines = logs(server, slug, "refuse-me")
    assert any("FMU: [ok] logAll: cannot import module" in line for line in lines), lines
