"""The co-simulations API on a real server with the mass-spring-damper pair (tests/fmus/
msd_mass, msd_spring): a folder uploaded as a zip, its FMUs inside it or uploaded to the twin,
run in its own process in batch and real-time modes, its results as Maestro's outputs.csv,
as columns for a chart and in the twin's history; stopped, deleted, stopped with the server;
and every bad upload a clear problem naming the file, the key or the limit."""

from __future__ import annotations

import io
import json
import tarfile
import time
import zipfile
from collections.abc import Iterator
from typing import Any

import httpx
import psutil
import pytest

from tests.conftest import ROOT, FmuFiles, Server, restart_server, start_server, stop_server
from tests.integration._util import (
    JSON_HEADERS,
    assert_problem,
    make_user,
    poll_until,
    twin_doc,
    unique,
)

pytestmark = pytest.mark.integration

ZIP = {"Content-Type": "application/zip"}
TAR = {"Content-Type": "application/x-tar"}
COSIMS = "/api/v1/cosims"
HOUR_NS = 3600 * 10**9
COSIM_FILES = ROOT / "tests" / "cosim_files"


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    # 1 MB: the FMUs of these tests are a few dozen kB, a larger upload tests the limit
    limits = {"TWINLINK_COSIM_MAX_MB": "1", "TWINLINK_MAX_COSIMS": "1"}
    srv = start_server(tmp_path_factory.mktemp("data"), limits)
    try:
        yield srv
    finally:
        stop_server(srv)


def multimodel(end: float = 2.0, step: float = 0.01, **extra: Any) -> dict[str, Any]:
    """Maestro's multi-model of the pair: a mass and a spring coupled by position and force."""
    return {
        "fmus": {"{msd1}": "msd_mass.fmu", "{msd2}": "msd_spring.fmu"},
        "connections": {
            "{msd1}.m1.x1": ["{msd2}.m2.x1"],
            "{msd1}.m1.v1": ["{msd2}.m2.v1"],
            "{msd2}.m2.fk": ["{msd1}.m1.fk"],
        },
        "parameters": {"{msd1}.m1.x1": 1.0, "{msd2}.m2.c2": 3.0},
        "logVariables": {"{msd1}.m1": ["x1", "v1"], "{msd2}.m2": ["x2"]},
        "algorithm": {"type": "fixed-step", "size": step},
        "startTime": 0.0,
        "endTime": end,
        **extra,
    }


def zip_of(files: dict[str, bytes]) -> bytes:
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as archive:
        for name, data in files.items():
            archive.writestr(name, data)
    return out.getvalue()


def tar_of(files: dict[str, bytes]) -> bytes:
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w") as archive:
        for name, data in files.items():
            info = tarfile.TarInfo(name)
            info.size = len(data)
            archive.addfile(info, io.BytesIO(data))
    return out.getvalue()


def folder(fmu_files: FmuFiles, model: dict[str, Any] | None = None) -> dict[str, bytes]:
    return {
        "msd.json": json.dumps(model or multimodel()).encode(),
        "msd_mass.fmu": fmu_files("msd_mass").read_bytes(),
        "msd_spring.fmu": fmu_files("msd_spring").read_bytes(),
    }


def make_twin(admin: httpx.Client) -> str:
    slug = unique("cosim")
    r = admin.post("/api/v1/apply", content=twin_doc(f"urn:test:{slug}").encode(),
                   headers={"Content-Type": "application/yaml"})  # fmt: skip
    assert r.status_code == 200, r.text
    return str(r.json()["results"][0]["slug"])


def ended(c: httpx.Client, cosim_id: int, timeout_s: float = 60.0) -> dict[str, Any]:
    def check() -> dict[str, Any] | None:
        view = c.get(f"{COSIMS}/{cosim_id}").json()
        return view if view["state"] != "running" else None

    return poll_until(check, f"co-simulation {cosim_id} to end", timeout_s)  # type: ignore[no-any-return]


def test_a_folder_runs_in_batch_into_its_csv_its_chart_and_the_twins_history(
    server: Server, fmu_files: FmuFiles
) -> None:
    with server.admin as admin:
        slug = make_twin(admin)
        r = admin.post(COSIMS, params={"name": "msd pair", "twin": slug, "prefix": "sim."},
                       content=zip_of(folder(fmu_files)), headers=ZIP)  # fmt: skip
        assert r.status_code == 201, r.text
        view = r.json()
        assert (view["name"], view["state"], view["twin"], view["owner"]) == (
            "msd pair", "created", slug, "admin")  # fmt: skip
        system = view["system"]
        assert system["source"] == "maestro" and system["loops"] == []
        assert [(i["name"], i["fmu"], i["kind"]) for i in system["instances"]] == [
            ("msd1.m1", "msd_mass.fmu", "co-simulation"),
            ("msd2.m2", "msd_spring.fmu", "co-simulation"),
        ]
        assert {"source": "msd2.m2.fk", "target": "msd1.m1.fk"} in system["connections"]
        assert system["algorithm"]["size"] == 0.01 and system["end_time"] == 2.0

        cosim_id = view["id"]
        assert_problem(admin.get(f"{COSIMS}/{cosim_id}/results.csv"), 404)  # not run yet
        assert admin.post(f"{COSIMS}/{cosim_id}/start").status_code == 200
        done = ended(admin, cosim_id)
        assert (done["state"], done["progress"]) == ("finished", 1.0), done
        assert "200 steps" in done["message"]  # the worker says how the run went
        assert done["columns"] == ["time", "{msd1}.m1.x1", "{msd1}.m1.v1", "{msd2}.m2.x2"]
        assert done["rows"] == 201 and done["sim_time"] == pytest.approx(2.0)

        csv_text = admin.get(f"{COSIMS}/{cosim_id}/results.csv").text
        lines = csv_text.splitlines()
        assert lines[0] == "time,{msd1}.m1.x1,{msd1}.m1.v1,{msd2}.m2.x2" and len(lines) == 202
        assert lines[1].split(",")[:2] == ["0.0", "1.0"]  # x1 starts where its parameter says

        chart = admin.get(f"{COSIMS}/{cosim_id}/results", params={"max_points": 50}).json()
        assert chart["columns"] == done["columns"]
        times = chart["data"][0]
        assert len(times) == 50 and times[0] == 0.0 and times[-1] == pytest.approx(2.0)
        last = [float(v) for v in lines[-1].split(",")]
        assert [column[-1] for column in chart["data"]] == pytest.approx(last)

        # the twin's history: the rows as signals {prefix}{column}, one sample per row
        streams = admin.get(f"/api/v1/twins/{slug}/streams").json()
        assert "sim.msd1.m1.x1" in json.dumps(streams)
        wanted = {"signals": "sim.msd1.m1.x1,sim.msd2.m2.x2", "start": "-1h",
                  "end": str(time.time_ns() + HOUR_NS), "limit": 1000}  # fmt: skip
        page = admin.get(f"/api/v1/twins/{slug}/streams/cosim/samples", params=wanted).json()
        assert len(page["rows"]) == 201, page
        first, last = page["rows"][0], page["rows"][-1]
        assert first["values"]["sim.msd1.m1.x1"] == 1.0
        assert last["values"]["sim.msd2.m2.x2"] == pytest.approx(float(lines[-1].split(",")[3]))
        # stamped with the wall clock at the start plus the simulated time
        assert last["time"] - first["time"] == 2 * 10**9


def test_a_realtime_run_is_paced_stopped_keeping_its_rows_and_started_again(
    server: Server, fmu_files: FmuFiles
) -> None:
    with server.admin as admin:
        # FMUs uploaded to the twin, named by file name from a multi-model sent alone
        slug = make_twin(admin)
        for name in ("msd_mass", "msd_spring"):
            r = admin.put(f"/api/v1/twins/{slug}/fmus/{name}.fmu",
                          content=fmu_files(name).read_bytes())  # fmt: skip
            assert r.status_code == 201, r.text
        body = json.dumps(multimodel(end=3600.0)).encode()
        r = admin.post(COSIMS, params={"twin": slug, "mode": "realtime", "factor": 2.0},
                       content=body, headers=JSON_HEADERS)  # fmt: skip
        assert r.status_code == 201, r.text
        cosim_id = r.json()["id"]
        running = admin.post(f"{COSIMS}/{cosim_id}/start").json()
        assert running["state"] == "running" and running["mode"] == "realtime"
        poll_until(lambda: (admin.get(f"{COSIMS}/{cosim_id}").json()["sim_time"] or 0) > 0,
                   "the paced run to make progress")  # fmt: skip
        assert_problem(admin.post(f"{COSIMS}/{cosim_id}/start"), 409)
        assert_problem(admin.delete(f"{COSIMS}/{cosim_id}"), 409)
        other = admin.post(COSIMS, params={"twin": slug}, content=body,
                           headers=JSON_HEADERS).json()["id"]  # fmt: skip
        full = assert_problem(admin.post(f"{COSIMS}/{other}/start"), 409)
        assert "max_cosims" in full["detail"]  # one at a time on this server
        assert admin.get(f"{COSIMS}/{other}").json()["state"] == "created"

        stopped = admin.post(f"{COSIMS}/{cosim_id}/stop").json()
        assert stopped["state"] == "stopped", stopped
        # paced at twice the wall clock: nowhere near the hour of simulated time
        assert 0 < stopped["sim_time"] < 600 and stopped["rows"] > 0
        kept = admin.get(f"{COSIMS}/{cosim_id}/results.csv").text.splitlines()
        assert len(kept) == stopped["rows"] + 1

        # started again, fast (factor 50) and to a near end: new results, finished
        admin.delete(f"{COSIMS}/{cosim_id}")  # ended: it may go
        assert_problem(admin.get(f"{COSIMS}/{cosim_id}"), 404)
        r = admin.post(COSIMS, params={"twin": slug, "mode": "realtime", "factor": 50},
                       content=json.dumps(multimodel(end=1.0)).encode(),
                       headers=JSON_HEADERS)  # fmt: skip
        cosim_id = r.json()["id"]
        admin.post(f"{COSIMS}/{cosim_id}/start")
        first = ended(admin, cosim_id)
        assert first["state"] == "finished" and first["rows"] == 101
        again = admin.post(f"{COSIMS}/{cosim_id}/start", json={"mode": "batch"}).json()
        assert again["mode"] == "batch"
        second = ended(admin, cosim_id)
        assert second["state"] == "finished" and second["rows"] == 101
        assert second["started_at"] >= first["ended_at"]


def test_who_may_create_see_and_run(server: Server, fmu_files: FmuFiles) -> None:
    token = make_user(server, unique("modeller"))
    with server.admin as admin, server.client(token) as user:
        slug = make_twin(admin)
        # FMU files in an upload are native code: admins only (TWINLINK_FMU_UPLOADERS)
        body = assert_problem(user.post(COSIMS, content=zip_of(folder(fmu_files)),
                                        headers=ZIP), 403)  # fmt: skip
        assert "FMU" in body["detail"]
        # writing into a twin's history needs its editor role
        body = assert_problem(user.post(COSIMS, params={"twin": slug},
                                        content=json.dumps(multimodel()).encode(),
                                        headers=JSON_HEADERS), 403)  # fmt: skip
        assert "editor" in body["detail"]
        # an admin's co-simulation is not another user's to see
        mine = admin.post(COSIMS, content=zip_of(folder(fmu_files)), headers=ZIP).json()
        assert_problem(user.get(f"{COSIMS}/{mine['id']}"), 404)
        assert_problem(user.post(f"{COSIMS}/{mine['id']}/start"), 404)
        assert all(c["id"] != mine["id"] for c in user.get(COSIMS).json()["cosims"])
        assert any(c["id"] == mine["id"] for c in admin.get(COSIMS).json()["cosims"])


def test_bad_uploads_are_refused_naming_the_file_the_key_or_the_limit(
    server: Server, fmu_files: FmuFiles
) -> None:
    with server.admin as admin:

        def refused(content: bytes, headers: dict[str, str], status: int = 422,
                    **params: Any) -> str:  # fmt: skip
            return str(assert_problem(admin.post(COSIMS, content=content, headers=headers,
                                                 params=params), status)["detail"])  # fmt: skip

        detail = refused(b'{"fmus": {"{a}": "a.fmu"},\n "connections": [}', JSON_HEADERS)
        assert "multimodel.json" in detail and "line 2" in detail
        detail = refused(json.dumps(multimodel()).encode(), JSON_HEADERS)
        assert "instance 'msd1.m1'" in detail and "'msd_mass.fmu'" in detail
        typo = multimodel(connections={"{msd1}.m1.x9": ["{msd2}.m2.x1"]})
        detail = refused(zip_of(folder(fmu_files, typo)), ZIP)
        assert "connections" in detail and "'x9'" in detail and "x1" in detail
        assert "/cosims/" not in detail  # the server's folders are not shown
        detail = refused(b"instances: [", {"Content-Type": "application/yaml"})
        assert "system.yaml" in detail and "line" in detail
        detail = refused(b"hello", {"Content-Type": "text/plain"})
        assert "application/json" in detail
        two = {**folder(fmu_files), "other.yaml": b"instances: {}\n"}
        assert "several documents" in refused(tar_of(two), TAR)
        assert "no .json" in refused(zip_of({"a.fmu": b"x"}), ZIP)
        assert "zip" in refused(b"not a zip", ZIP)
        assert "cosim_max_mb" in refused(b"x" * (2**20 + 1), ZIP, 413)
        assert "mode" in refused(json.dumps(multimodel()).encode(), JSON_HEADERS, mode="fast")
        assert "factor" in refused(json.dumps(multimodel()).encode(), JSON_HEADERS, factor=0)
        evil = zip_of({"../escape.json": b"{}"})
        assert "'..'" in refused(evil, ZIP) or "goes up" in refused(evil, ZIP)
        # no end time: a batch run cannot start; nothing of it ran
        endless = multimodel()
        del endless["endTime"]
        made = admin.post(COSIMS, content=zip_of(folder(fmu_files, endless)), headers=ZIP)
        assert made.status_code == 201, made.text
        detail = str(assert_problem(admin.post(f"{COSIMS}/{made.json()['id']}/start"),
                                    422)["detail"])  # fmt: skip
        assert "end time" in detail
        assert admin.get(f"{COSIMS}/{made.json()['id']}").json()["state"] == "created"
        assert_problem(admin.get(f"{COSIMS}/999999"), 404)


def _workers(server: Server) -> list[psutil.Process]:
    """The co-simulation workers the server runs (its children, in sessions of their own)."""
    children = psutil.Process(server.process.pid).children(recursive=True)
    return [p for p in children if "twinlink.cosim.worker" in " ".join(p.cmdline())]


def _gone(processes: list[psutil.Process]) -> bool:
    return not [p for p in processes if p.is_running() and p.status() != "zombie"]


def _start_endless(admin: httpx.Client, fmu_files: FmuFiles) -> int:
    r = admin.post(COSIMS, params={"mode": "realtime"},
                   content=zip_of(folder(fmu_files, multimodel(end=36000.0))),
                   headers=ZIP)  # fmt: skip
    cosim_id: int = r.json()["id"]
    admin.post(f"{COSIMS}/{cosim_id}/start")
    poll_until(lambda: (admin.get(f"{COSIMS}/{cosim_id}").json()["sim_time"] or 0) > 0,
               "the run to make progress")  # fmt: skip
    return cosim_id


def test_a_server_stop_stops_its_runs_and_a_crash_fails_them(
    tmp_path_factory: pytest.TempPathFactory, fmu_files: FmuFiles
) -> None:
    srv = start_server(tmp_path_factory.mktemp("data"))
    try:
        with srv.admin as admin:
            cosim_id = _start_endless(admin, fmu_files)
        workers = _workers(srv)
        assert workers
        stop_server(srv)
        assert _gone(workers)
        srv = restart_server(srv)
        with srv.admin as admin:
            view = admin.get(f"{COSIMS}/{cosim_id}").json()
            assert view["state"] == "stopped" and view["rows"] > 0, view
            # killed: the worker outlives it (a session of its own) until the next start
            crashed_id = _start_endless(admin, fmu_files)
        workers = _workers(srv)
        assert workers
        srv.process.kill()  # SIGKILL: the server dies, its worker (own session) may not
        stop_server(srv)
        srv = restart_server(srv)
        poll_until(lambda: _gone(workers), "the leftover worker to be killed")
        with srv.admin as admin:
            view = admin.get(f"{COSIMS}/{crashed_id}").json()
            assert view["state"] == "failed" and "server stopped" in view["message"], view
            restarted = admin.post(f"{COSIMS}/{crashed_id}/start", json={"mode": "batch"})
            assert restarted.status_code == 200, restarted.text
            admin.post(f"{COSIMS}/{crashed_id}/stop")
    finally:
        stop_server(srv)


def test_the_tools_files_run_unchanged_ssp_yaml_and_a_multi_model_with_its_coe_json(
    server: Server, fmu_files: FmuFiles
) -> None:
    """The fixtures modelled on the tools' files (tests/cosim_files), FMUs under their names."""
    fmus = {"MassSpringDamper1.fmu": fmu_files("msd_mass").read_bytes(),
            "MassSpringDamper2.fmu": fmu_files("msd_spring").read_bytes()}  # fmt: skip
    ssp_dir = COSIM_FILES / "msd_ssp"
    ssp = zip_of({
        **{p.relative_to(ssp_dir).as_posix(): p.read_bytes()
           for p in ssp_dir.rglob("*") if p.is_file()},
        **{f"resources/{name}": data for name, data in fmus.items()},
    })  # fmt: skip
    msd = COSIM_FILES / "msd"
    maestro = tar_of({"mm.json": (msd / "mm.json").read_bytes(),
                      "coe.json": (msd / "coe.json").read_bytes(), **fmus})  # fmt: skip
    with server.admin as admin:
        slug = make_twin(admin)
        for name, data in fmus.items():
            assert admin.put(f"/api/v1/twins/{slug}/fmus/{name}", content=data).status_code == 201
        made = [
            admin.post(COSIMS, content=ssp, headers=ZIP),
            admin.post(COSIMS, params={"twin": slug}, content=(msd / "msd.yaml").read_bytes(),
                       headers={"Content-Type": "application/yaml"}),
            admin.post(COSIMS, content=maestro, headers=TAR),
        ]  # fmt: skip
        for r in made:
            assert r.status_code == 201, r.text
        assert [r.json()["system"]["source"] for r in made] == ["ssp", "yaml", "maestro"]
        # coe.json's algorithm and end time complete mm.json's system
        assert made[2].json()["system"]["algorithm"]["size"] == 0.001
        runs = []
        for r in made:  # one at a time: the server's max_cosims is 1
            assert admin.post(f"{COSIMS}/{r.json()['id']}/start").status_code == 200
            runs.append(ended(admin, r.json()["id"]))
        assert [run["state"] for run in runs] == ["finished"] * 3, runs
        assert [run["sim_time"] for run in runs] == pytest.approx([10.0] * 3)
        assert "{msd2}.msd2i.x2" in runs[2]["columns"]  # Maestro's own column names
        assert "msd2.msd2i.x2" in runs[1]["columns"]
        # an SSP archive names nothing to record: every output is, as `twinlink cosim run` does
        assert {"msd1.msd1i.x1", "msd1.msd1i.v1", "msd2.msd2i.fk"} <= {
            c.replace("{", "").replace("}", "") for c in runs[0]["columns"]
        }, runs[0]["columns"]


def test_library_models_resolve_pinned(server: Server, fmu_files: FmuFiles) -> None:
    name = unique("msd-pair")
    fmus = {f"{n}.fmu": fmu_files(n).read_bytes() for n in ("msd_mass", "msd_spring")}
    with server.admin as admin:
        r = admin.post(f"/api/v1/library/me/models/{name}/versions", params={"format": "zip"},
                       content=zip_of(fmus))  # fmt: skip
        assert r.status_code == 201, r.text
        model = multimodel(fmus={"{msd1}": f"lib:models/{name}#msd_mass.fmu",
                                 "{msd2}": f"lib:models/{name}@latest#msd_spring.fmu"})  # fmt: skip
        made = admin.post(COSIMS, content=json.dumps(model).encode(), headers=JSON_HEADERS)
        assert made.status_code == 201, made.text
        cosim_id = made.json()["id"]
        admin.post(f"{COSIMS}/{cosim_id}/start")
        assert ended(admin, cosim_id)["state"] == "finished"
        missing = multimodel(fmus={"{msd1}": f"lib:models/{name}#nope.fmu",
                                   "{msd2}": "msd_spring.fmu"})  # fmt: skip
        detail = assert_problem(admin.post(COSIMS, content=json.dumps(missing).encode(),
                                           headers=JSON_HEADERS), 422)["detail"]  # fmt: skip
        assert "instance 'msd1.m1'" in detail and "nope.fmu" in detail
