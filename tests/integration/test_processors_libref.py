"""FMU processors whose FMU is a library asset (`fmu: lib:models/...`), on a real server: the
reference pinned at create, the version held while a processor uses it, a moved tag leaving
a processor as it was, and references that cannot be used refused at create."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import FmuFiles, Server, start_server, stop_server
from tests.integration._live import device_twin
from tests.integration._processors import (
    BLUEPRINTS,
    MS,
    T0,
    create,
    post,
    samples_until,
    wait_for,
    watching,
)
from tests.integration._processors import server as server  # module fixture
from tests.integration._util import assert_problem, unique

pytestmark = pytest.mark.integration

# Tingen, NTNU thesis table 3.1 (as test_fmu_processors)
L, I_AREA, E = 0.300, 2.1e-12, 210e9


def push_fmu(server: Server, name: str, path: Path, tag: str = "1.0.0") -> dict[str, Any]:
    """Push one .fmu file as a version of common/models/<name>, tagged `tag`."""
    with server.admin as admin:
        r = admin.post(
            f"/api/v1/library/common/models/{name}/versions",
            params=[("format", "file"), ("filename", "tingen.fmu"), ("tag", tag)],
            content=path.read_bytes(),
        )
    assert r.status_code in (200, 201), r.text
    return r.json()["version"]  # type: ignore[no-any-return]


def fmu_processor(slug: str, ref: str, **extra: Any) -> dict[str, Any]:
    return {
        "name": "beam",
        "blueprint": "fmu",
        "inputs": {"F": {"signal": "force"}},
        "params": {"fmu": ref, "outputs": ["theta"], "parameters": {"zeta": 1.0}},
        **extra,
    }


def fmi_version(view: dict[str, Any]) -> str:
    """The FMI version of the FMU the processor's worker runs."""
    return str(view["running"]["describe"]["fmi_version"])


def started_anew(view: dict[str, Any], before: dict[str, Any]) -> bool:
    """Whether another worker than `before`'s runs (its view says what it runs)."""
    return view["state"] == "running" and view["pid"] not in (None, before["pid"])


def test_a_library_fmu_is_pinned_and_runs(server: Server, fmu_files: FmuFiles) -> None:
    name = unique("beam")
    version = push_fmu(server, name, fmu_files("tingen"))
    slug, [device] = device_twin(server)
    made = create(server, slug, **fmu_processor(slug, f"lib:models/{name}@1.0.0"))
    pinned = f"lib:common/models/{name}@{version['digest']}#tingen.fmu"
    assert made["params"]["fmu"] == pinned
    wait_for(server, slug, "beam", lambda p: p["state"] == "running")
    with watching(server, slug, "beam") as ws:
        post(server, device, 1, [{"force": 2.0}] * 2000)  # 2 N for 2 s: the beam settles
        got = samples_until(ws, lambda s: len(s) >= 2000)
    theta = 2.0 * L**2 / (2 * E * I_AREA)
    assert math.isclose(got[-1]["values"]["theta"], theta, rel_tol=1e-6)
    assert got[-1]["time"] == T0 + 1999 * MS


def test_a_held_version_cannot_be_deleted_until_its_processor_is(
    server: Server, fmu_files: FmuFiles
) -> None:
    name = unique("beam")
    version = push_fmu(server, name, fmu_files("tingen"))
    slug, _ = device_twin(server)
    create(server, slug, **fmu_processor(slug, f"lib:common/models/{name}", enabled=False))
    path = f"/api/v1/library/common/models/{name}/versions/{version['digest']}"
    with server.admin as admin:
        body = assert_problem(admin.delete(path), 409)
        assert "processor:" in body["detail"], body
        assert assert_problem(admin.delete(f"/api/v1/library/common/models/{name}"), 409)
        assert admin.delete(f"/api/v1/twins/{slug}/processors/beam").status_code == 204
        assert admin.delete(path).status_code == 204


def test_deleting_the_twin_releases_its_processors_versions(
    server: Server, fmu_files: FmuFiles
) -> None:
    name = unique("beam")
    version = push_fmu(server, name, fmu_files("tingen"))
    slug, _ = device_twin(server)
    create(server, slug, **fmu_processor(slug, f"lib:models/{name}", enabled=False))
    path = f"/api/v1/library/common/models/{name}/versions/{version['digest']}"
    with server.admin as admin:
        assert admin.delete(path).status_code == 409
        assert admin.delete(f"/api/v1/twins/{slug}").status_code == 200
        # The hold goes with the twin (released just after its delete answers).
        deadline = time.monotonic() + 30
        while (r := admin.delete(path)).status_code == 409 and time.monotonic() < deadline:
            time.sleep(0.05)  # polling the real state
        assert r.status_code == 204, r.text


def test_a_moved_tag_leaves_an_existing_processor_on_its_version(
    server: Server, fmu_files: FmuFiles
) -> None:
    name = unique("beam")
    first = push_fmu(server, name, fmu_files("tingen"))
    slug, _ = device_twin(server)
    create(server, slug, **fmu_processor(slug, f"lib:models/{name}@1.0.0"))
    running = wait_for(server, slug, "beam", lambda p: "describe" in p["running"])
    assert fmi_version(running) == "2.0"
    second = push_fmu(server, name, fmu_files("tingen3"))  # 1.0.0 moves to the FMI 3 build
    assert second["digest"] != first["digest"]
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors/beam/restart")
        assert r.status_code == 200, r.text
    again = wait_for(server, slug, "beam", lambda p: started_anew(p, running))
    assert again["params"]["fmu"].split("@")[1] == f"{first['digest']}#tingen.fmu"
    assert fmi_version(again) == "2.0"
    newer = create(server, slug, **{**fmu_processor(slug, f"lib:models/{name}@1.0.0"),
                                    "name": "beam3", "output": "beam3"})  # fmt: skip
    assert newer["params"]["fmu"].split("@")[1] == f"{second['digest']}#tingen.fmu"
    # Moved to the other version, the processor no longer holds the first one. Changed while
    # its worker starts (a restart just asked for), the worker runs the new FMU.
    with server.admin as admin:
        assert admin.post(f"/api/v1/twins/{slug}/processors/beam/restart").status_code == 200
        r = admin.patch(
            f"/api/v1/twins/{slug}/processors/beam",
            json={"params": {**fmu_processor(slug, newer["params"]["fmu"])["params"]}},
        )
        assert r.status_code == 200, r.text
        moved = wait_for(server, slug, "beam", lambda p: started_anew(p, again)
                         and fmi_version(p) == "3.0")  # fmt: skip
        assert moved["params"]["fmu"] == newer["params"]["fmu"]  # restarted on the FMI 3 build
        old = f"/api/v1/library/common/models/{name}/versions/{first['digest']}"
        assert admin.delete(old).status_code == 204


def test_a_library_fmu_processor_runs_again_after_a_restart(
    fmu_files: FmuFiles, tmp_path: Path
) -> None:
    env = {"TWINLINK_BLUEPRINTS_DIR": str(BLUEPRINTS)}
    first = start_server(tmp_path, env)
    try:
        push_fmu(first, "beam", fmu_files("tingen"))
        slug, _ = device_twin(first)
        create(first, slug, **fmu_processor(slug, "lib:models/beam"))
        wait_for(first, slug, "beam", lambda p: "describe" in p["running"])
    finally:
        stop_server(first)
    again = start_server(tmp_path, env, token=first.admin_token, password=first.admin_password)
    try:  # its file found again, with no person's rights at hand
        view = wait_for(again, slug, "beam", lambda p: "describe" in p["running"])
        assert fmi_version(view) == "2.0" and view["last_error"] is None
    finally:
        stop_server(again)


@pytest.mark.parametrize(
    ("ref", "params", "words"),
    [
        ("lib:models/{missing}@1.0.0", {}, "{missing}"),
        ("lib:models/{name}@9.9.9", {}, "9.9.9"),
        ("lib:models/{name}", {"outputs": ["no_such_output"]}, "no_such_output"),
        ("lib:models/{name}", {"parameters": {"no_such_param": 1.0}}, "no_such_param"),
        ("lib:data/{name}", {}, "models"),
    ],
)
def test_a_library_fmu_that_cannot_be_used_is_refused_at_create(
    server: Server, fmu_files: FmuFiles, ref: str, params: dict[str, Any], words: str
) -> None:
    name, missing = unique("beam"), unique("missing")
    push_fmu(server, name, fmu_files("tingen"))
    slug, _ = device_twin(server)
    body = fmu_processor(slug, ref.format(name=name, missing=missing))
    body["params"].update(params)
    with server.admin as admin:
        r = admin.post(f"/api/v1/twins/{slug}/processors", json=body)
        problem = assert_problem(r, 422)
        assert words.format(missing=missing) in problem["detail"], problem
        assert admin.get(f"/api/v1/twins/{slug}/processors").json()["processors"] == []
