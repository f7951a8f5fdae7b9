"""A deployment running a co-simulation: the twin package examples/library/msd-cosim, pushed
with its two FMUs as the README says and deployed on a real server, runs `twinlink cosim run`
in its execute phase as the device `sim`; the run succeeds and the twin's history holds the
co-simulated signals, the rows of the CSV the run left in the deployment's folder. Paced, it
streams while it runs, and stopping the deployment ends it with what it had sent."""

from __future__ import annotations

import csv
import io
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import EXAMPLES, FmuFiles, Server, start_server, stop_server
from tests.integration._util import poll_until
from twinlink.client._tar import folder_files, pack

pytestmark = pytest.mark.integration

PACKAGE = EXAMPLES / "library" / "msd-cosim"
SIGNALS = ["msd1.msd1i.x1", "msd1.msd1i.v1", "msd2.msd2i.x2", "msd2.msd2i.v2", "msd2.msd2i.fk"]


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        yield srv
    finally:
        stop_server(srv)


def _push(server: Server, kind: str, name: str, source: Path) -> None:
    if source.is_dir():
        body, query = b"".join(pack(folder_files(source))), {"format": "tar"}
    else:
        body, query = source.read_bytes(), {"format": "file", "filename": source.name}
    with server.admin as admin:
        r = admin.post(f"/api/v1/library/common/{kind}/{name}/versions",
                       params={**query, "tag": "1.0.0"}, content=body)  # fmt: skip
    assert r.status_code == 201, r.text


@pytest.fixture(scope="module")
def pushed(server: Server, fmu_files: FmuFiles, tmp_path_factory: pytest.TempPathFactory) -> str:
    """The FMUs under the names examples/cosim/build.sh gives them, then the package."""
    folder = tmp_path_factory.mktemp("fmus")
    for source, name, asset in (("msd_mass", "MassSpringDamper1.fmu", "msd-mass"),
                                ("msd_spring", "MassSpringDamper2.fmu", "msd-spring")):  # fmt: skip
        shutil.copyfile(fmu_files(source), folder / name)
        _push(server, "models", asset, folder / name)
    _push(server, "twins", "msd-cosim", PACKAGE)
    return "msd-cosim@1.0.0"


def _deploy(server: Server, package: str, name: str, **parameters: Any) -> dict[str, Any]:
    with server.admin as admin:
        r = admin.post("/api/v1/deployments", json={
            "package": package, "name": name, "parameters": parameters, "start": True,
        })  # fmt: skip
    assert r.status_code == 201, r.text
    assert set(r.json()["device_tokens"]) == {"sim"}
    return r.json()  # type: ignore[no-any-return]


def _execute_run(server: Server, name: str) -> dict[str, Any] | None:
    with server.admin as admin:
        runs = admin.get(f"/api/v1/deployments/{name}/runs").json()["runs"]
    found = [r for r in runs if r["phase"] == "execute"]
    return found[0] if found else None


def _ended(server: Server, name: str) -> dict[str, Any]:
    def ended() -> dict[str, Any] | None:
        run = _execute_run(server, name)
        return run if run and run["state"] not in ("queued", "running") else None

    run: dict[str, Any] = poll_until(ended, f"{name}'s execute run to end", 120)
    return run


def _log(server: Server, run_id: int) -> str:
    with server.admin as admin:
        return admin.get(f"/api/v1/runs/{run_id}/log").text


def _history(server: Server, slug: str) -> list[dict[str, Any]]:
    rows: list[dict[str, Any]] = []
    params: dict[str, Any] = {"limit": 100_000}
    with server.admin as admin:
        while True:
            r = admin.get(f"/api/v1/twins/{slug}/streams/cosim/samples", params=params)
            if r.status_code == 404:
                return rows  # no such stream yet
            assert r.status_code == 200, r.text
            page = r.json()
            rows += page["rows"]
            if not page.get("next_cursor"):
                return rows
            params["cursor"] = page["next_cursor"]


def test_the_execute_phase_runs_the_cosimulation_into_the_twins_history(
    server: Server, pushed: str
) -> None:
    made = _deploy(server, pushed, "msd-a")
    run = _ended(server, "msd-a")
    log = _log(server, run["id"])
    assert (run["state"], run["exit_code"]) == ("succeeded", 0), log
    assert "msd.json: finished: 1001 rows to t = 10 s" in log and "sent 1001 samples" in log
    stored = _history(server, "msd-a")
    assert len(stored) == 1001
    assert all(set(s["values"]) == set(SIGNALS) for s in stored)
    assert [s["time"] - stored[0]["time"] for s in stored[:2]] == [0, 10_000_000]
    # the rows stored are those of the CSV the run wrote in the deployment's folder
    work = server.data_dir / "deployments" / str(made["deployment"]["id"]) / "work"
    written = list(csv.reader(io.StringIO((work / f"outputs-{run['id']}.csv").read_text())))
    assert written[0][1:] == ["{msd1}.msd1i.x1", "{msd1}.msd1i.v1", "{msd2}.msd2i.x2",
                              "{msd2}.msd2i.v2", "{msd2}.msd2i.fk"]  # fmt: skip
    for row, sample in zip(written[1:], stored, strict=True):
        assert [sample["values"][s] for s in SIGNALS] == [float(v) for v in row[1:]]
    assert stored[0]["values"]["msd1.msd1i.x1"] == 1.0  # the multi-model's start value


def test_a_paced_run_streams_while_it_runs_and_a_stop_ends_it(server: Server, pushed: str) -> None:
    _deploy(server, pushed, "msd-b", realtime=1.0, end_time=3600)
    poll_until(lambda: len(_history(server, "msd-b")) >= 10, "the first rows, live", 60)
    running = _execute_run(server, "msd-b")
    assert running is not None and running["state"] == "running"  # an hour to go
    with server.admin as admin:
        r = admin.post("/api/v1/deployments/msd-b/stop")
        assert r.status_code == 200, r.text
    run = _ended(server, "msd-b")
    log = _log(server, run["id"])
    # SIGTERM: the run stopped after its step and sent every row it had computed
    assert "ended early (stopped at t = " in log, log
    stored = _history(server, "msd-b")
    assert f"sent {len(stored)} samples" in log
    assert stored[-1]["time"] - stored[0]["time"] < 3600 * 10**9
