"""FMU processors on a real server: upload and inspect, the Tingen FMU on live samples, and
misbehaving FMUs (a segfault in native code, a leak) isolated in their worker processes."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import FmuFiles, Server, stop_server
from tests.integration._live import device_twin
from tests.integration._processors import (
    MS,
    T0,
    create,
    events,
    post,
    processor_server,
    samples_until,
    wait_for,
    watching,
)
from tests.integration._processors import server as server  # module fixture
from tests.integration._util import make_user, unique

pytestmark = pytest.mark.integration

# Tingen, NTNU thesis table 3.1
L, I_AREA, E, C_FIBER = 0.300, 2.1e-12, 210e9, 0.0005


def upload(server: Server, slug: str, path: Path, name: str | None = None) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.put(
            f"/api/v1/twins/{slug}/fmus/{name or path.name}",
            content=path.read_bytes(),
            headers={"Content-Type": "application/octet-stream"},
        )
    assert r.status_code == 201, r.text
    return r.json()  # type: ignore[no-any-return]


def test_an_uploaded_fmu_lists_its_variables(server: Server, fmu_files: FmuFiles) -> None:
    slug, _ = device_twin(server)
    info = upload(server, slug, fmu_files("tingen"), "Tingen.fmu")
    assert info["fmi_version"] == "2.0" and info["size"] == fmu_files("tingen").stat().st_size
    variables = {v["name"]: v for v in info["variables"]}
    assert variables["F"]["causality"] == "input" and variables["F"]["unit"] == "N"
    assert (variables["F"]["min"], variables["F"]["max"]) == (-50.0, 50.0)
    assert variables["theta"]["causality"] == "output"
    with server.admin as admin:
        listed = admin.get(f"/api/v1/twins/{slug}/fmus").json()["fmus"]
        assert [f["name"] for f in listed] == ["Tingen.fmu"] and "variables" not in listed[0]
        assert admin.get(f"/api/v1/twins/{slug}/fmus/Tingen.fmu").json()["variables"]


@pytest.mark.parametrize(
    ("name", "body", "status", "words"),
    [
        ("junk.fmu", b"not a zip at all", 422, "not a usable FMU"),
        ("../evil.fmu", b"x", 404, ""),
        ("evil.exe", b"x", 422, "not an FMU file name"),
        ("empty.fmu", b"", 422, "empty"),
    ],
)
def test_bad_uploads_are_refused_and_leave_nothing(
    server: Server, name: str, body: bytes, status: int, words: str
) -> None:
    slug, _ = device_twin(server)
    with server.admin as admin:
        r = admin.put(f"/api/v1/twins/{slug}/fmus/{name}", content=body)
        assert r.status_code == status and words in r.text, r.text
        assert admin.get(f"/api/v1/twins/{slug}/fmus").json()["fmus"] == []


def test_the_tingen_fmu_gives_the_beam_result_on_live_samples(
    server: Server, fmu_files: FmuFiles
) -> None:
    slug, [device] = device_twin(server)
    upload(server, slug, fmu_files("tingen"), "Tingen.fmu")
    create(
        server, slug, name="fmu", blueprint="fmu",
        inputs={"F": {"signal": "force", "scale": 0.5}},
        params={"fmu": "Tingen.fmu", "outputs": ["theta", "sigma"],
                "parameters": {"zeta": 1.0}},
    )  # fmt: skip
    wait_for(server, slug, "fmu", lambda p: p["state"] == "running")
    with watching(server, slug, "fmu") as ws:
        # 4 N measured, scaled to 2 N, held for 2 s at 1 kHz: the beam settles (critical damping)
        post(server, device, 1, [{"force": 4.0}] * 2000)
        got = samples_until(ws, lambda s: len(s) >= 2000)
    force = 2.0
    theta, sigma = force * L**2 / (2 * E * I_AREA), force * L * C_FIBER / I_AREA
    last = got[-1]["values"]
    assert math.isclose(last["theta"], theta, rel_tol=1e-6)
    assert math.isclose(last["sigma"], sigma, rel_tol=1e-6)
    assert got[0]["time"] == T0 and got[-1]["time"] == T0 + 1999 * MS
    assert got[1]["values"]["theta"] < theta / 100  # it starts at rest, not at the end value


def test_a_segfaulting_fmu_is_isolated_restarted_and_reported(
    server: Server, fmu_files: FmuFiles
) -> None:
    slug, [device] = device_twin(server)
    upload(server, slug, fmu_files("crash"))
    create(server, slug, name="crashy", blueprint="fmu", inputs={"u": "x"},
           params={"fmu": "crash.fmu", "parameters": {"threshold": 10.0}})  # fmt: skip
    create(server, slug, name="steady", blueprint="test-gain", params={"signals": ["x"]})
    first = wait_for(server, slug, "crashy", lambda p: p["state"] == "running")
    wait_for(server, slug, "steady", lambda p: p["state"] == "running")
    with watching(server, slug, "steady") as ws:
        post(server, device, 1, [{"x": 1.0}, {"x": 50.0}])  # 50 > threshold: SIGSEGV
        wait_for(server, slug, "crashy", lambda p: p["stats"]["restarts"] == 1)
        post(server, device, 2, [{"x": 3.0}], t0=T0 + 10 * MS)
        got = samples_until(ws, lambda s: len(s) >= 3)
    assert [s["values"]["x"] for s in got] == [2.0, 100.0, 6.0]  # the neighbour went on
    [event] = events(server, slug, "crashy", "crashed")
    assert "SIGSEGV" in event["message"] and event["data"]["exit_code"] == -11
    again = wait_for(server, slug, "crashy", lambda p: p["state"] == "running")
    assert again["pid"] != first["pid"] and again["stats"]["crashes"] == 1
    with watching(server, slug, "crashy") as ws:
        post(server, device, 3, [{"x": 2.0}], t0=T0 + 20 * MS)
        [sample] = samples_until(ws, lambda s: len(s) >= 1)
    assert sample["values"] == {"y": 4.0}  # the restarted worker computes again
    with server.admin as admin:
        assert admin.get("/healthz").status_code == 200


def test_a_leaking_fmu_is_restarted_at_its_memory_limit(
    server: Server, fmu_files: FmuFiles
) -> None:
    slug, [device] = device_twin(server)
    upload(server, slug, fmu_files("leak"))
    create(server, slug, name="leaky", blueprint="fmu", inputs={"u": "x"}, memory_limit_mb=200,
           params={"fmu": "leak.fmu", "parameters": {"mb_per_step": 20.0}})  # fmt: skip
    wait_for(server, slug, "leaky", lambda p: p["state"] == "running")
    post(server, device, 1, [{"x": 1.0}] * 20)  # 400 MB over 20 steps
    wait_for(server, slug, "leaky", lambda p: p["stats"]["restarts"] >= 1)
    [event, *_] = events(server, slug, "leaky", "memory_limit")
    assert event["data"]["rss_bytes"] > 200 * 2**20


def test_fmi_errors_are_reported_with_the_fmus_own_message(
    server: Server, fmu_files: FmuFiles
) -> None:
    slug, [device] = device_twin(server)
    upload(server, slug, fmu_files("status"))
    create(server, slug, name="strict", blueprint="fmu", inputs={"u": "x"},
           params={"fmu": "status.fmu"})  # fmt: skip
    wait_for(server, slug, "strict", lambda p: p["state"] == "running")
    post(server, device, 1, [{"x": 1.0}, {"x": -2.0}])
    wait_for(server, slug, "strict", lambda p: p["stats"]["restarts"] >= 1)
    [event, *_] = events(server, slug, "strict", "failed")
    assert "negative input u=-2" in event["message"], event


def test_an_fmu_in_use_cannot_be_deleted(server: Server, fmu_files: FmuFiles) -> None:
    slug, _ = device_twin(server)
    upload(server, slug, fmu_files("tingen"), "T.fmu")
    create(server, slug, name="sim", blueprint="fmu", params={"fmu": "T.fmu"}, enabled=False)
    with server.admin as admin:
        r = admin.delete(f"/api/v1/twins/{slug}/fmus/T.fmu")
        assert r.status_code == 409 and "sim" in r.text, r.text
        assert admin.delete(f"/api/v1/twins/{slug}/processors/sim").status_code == 204
        assert admin.delete(f"/api/v1/twins/{slug}/fmus/T.fmu").status_code == 204
        assert admin.get(f"/api/v1/twins/{slug}/fmus/T.fmu").status_code == 404


def test_only_admins_upload_fmus_unless_editors_are_allowed(
    server: Server, fmu_files: FmuFiles, tmp_path: Path
) -> None:
    slug, _ = device_twin(server)
    name = unique("editor")
    token = make_user(server, name)
    with server.admin as admin:
        assert admin.put(f"/api/v1/twins/{slug}/roles/{name}", json={"role": "editor"}).is_success
    body = fmu_files("tingen").read_bytes()
    with server.client(token) as editor:
        r = editor.put(f"/api/v1/twins/{slug}/fmus/T.fmu", content=body)
        assert r.status_code == 403 and "native code" in r.text, r.text
    other = processor_server(tmp_path, TWINLINK_FMU_UPLOADERS="editors")
    try:
        slug, _ = device_twin(other)
        token = make_user(other, name)
        with other.admin as admin:
            assert admin.put(
                f"/api/v1/twins/{slug}/roles/{name}", json={"role": "editor"}
            ).is_success
        with other.client(token) as editor:
            r = editor.put(f"/api/v1/twins/{slug}/fmus/T.fmu", content=body)
            assert r.status_code == 201, r.text
    finally:
        stop_server(other)
