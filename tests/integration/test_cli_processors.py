"""`twinlink blueprints`, `twinlink processors` and `twinlink fmus`, run as subprocesses."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.conftest import FmuFiles, Server
from tests.integration._live import device_twin
from tests.integration._processors import server as server  # module fixture
from tests.integration._processors import wait_for
from tests.integration.test_cli import Cli

pytestmark = pytest.mark.integration


@pytest.fixture(scope="module")
def cli(server: Server, tmp_path_factory: pytest.TempPathFactory) -> Cli:
    return Cli(server, tmp_path_factory.mktemp("config"))


def test_an_fmu_processor_from_the_command_line(
    cli: Cli, server: Server, fmu_files: FmuFiles, tmp_path: Path
) -> None:
    slug, _ = device_twin(server)
    uploaded = cli("fmus", "upload", slug, str(fmu_files("tingen")), "--name", "T.fmu").ok()
    assert "uploaded T.fmu" in uploaded.out
    assert any(line.split()[:2] == ["F", "input"] for line in uploaded.out.splitlines())
    assert "T.fmu" in cli("fmus", "ls", slug).ok().out
    made = cli(
        "processors", "create", slug, "sim", "fmu", "-i", "F=force:0.5",
        "-p", "fmu=T.fmu", "-p", 'outputs=["theta"]',
    ).ok()  # fmt: skip
    assert made.out.split()[:2] == ["sim", "fmu"]
    wait_for(server, slug, "sim", lambda p: p["state"] == "running")
    shown = json.loads(cli("processors", "show", slug, "sim", "--json").ok().out)
    assert shown["inputs"] == {"F": {"signal": "force", "scale": 0.5, "offset": 0.0}}
    assert shown["running"]["outputs"] == ["theta"]
    assert (
        "state kept" in cli("processors", "set", slug, "sim", 'parameters={"zeta": 0.5}').ok().out
    )
    assert "started" in cli("processors", "events", slug, "sim").ok().out
    assert "sim: stopped" in cli("processors", "stop", slug, "sim").ok().out
    refused = cli("fmus", "rm", slug, "T.fmu")
    assert refused.code != 0 and "used by processor(s) sim" in refused.err
    cli("processors", "rm", slug, "sim").ok()
    cli("fmus", "rm", slug, "T.fmu").ok()
    spec = tmp_path / "smooth.yaml"
    spec.write_text(
        "name: smooth\nblueprint: lowpass\n"
        "params: {signals: [x], cutoff_hz: 2, sample_rate_hz: 100}\n"
    )
    cli("processors", "create", slug, "-f", str(spec), "--stopped").ok()
    assert "smooth" in cli("processors", "ls", slug).ok().out


def test_blueprints_and_mistakes(cli: Cli, server: Server) -> None:
    listed = cli("blueprints").ok().out
    assert {"fmu", "lowpass", "expression", "trigger", "test-gain"} <= {
        line.split()[0] for line in listed.splitlines()
    }
    lowpass = cli("blueprints", "lowpass").ok().out
    assert "cutoff_hz" in lowpass and "sample_rate_hz" in lowpass
    slug, _ = device_twin(server)
    wrong = cli("processors", "create", slug, "p", "nope")
    assert wrong.code != 0 and "no blueprint 'nope'" in wrong.err and "Traceback" not in wrong.err
    bad_input = cli("processors", "create", slug, "p", "lowpass", "-i", "x=y:big")
    assert bad_input.code != 0 and "scale and offset must be numbers" in bad_input.err
