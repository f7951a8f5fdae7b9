"""examples/notebooks/deployment.ipynb, its code cells run in order against a real server as
a kernel would run them (one namespace, the notebook's folder as working dir): the Tingen
package pushed, deployed, started, its history read as DataFrames, a run followed, the
deployment reconfigured, stopped and terminated."""

from __future__ import annotations

import contextlib
import io
import json
import tempfile
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import EXAMPLES, Server

pytestmark = pytest.mark.integration

NOTEBOOK = EXAMPLES / "notebooks" / "deployment.ipynb"


def _cells() -> list[str]:
    notebook = json.loads(NOTEBOOK.read_text("utf-8"))
    return ["".join(c["source"]) for c in notebook["cells"] if c["cell_type"] == "code"]


def test_the_notebook_drives_a_deployment_end_to_end(
    server: Server, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))  # where the notebook builds the FMU
    monkeypatch.setenv("TWINLINK_URL", server.url)
    monkeypatch.setenv("TWINLINK_TOKEN", server.admin_token)
    monkeypatch.chdir(NOTEBOOK.parent)
    namespace: dict[str, Any] = {"__name__": "__main__"}
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        for i, source in enumerate(_cells()):
            try:
                exec(compile(source, f"{NOTEBOOK.name}[{i}]", "exec"), namespace)
            except Exception as err:
                raise AssertionError(f"cell {i} failed:\n{printed.getvalue()}") from err
    assert [p["asset"]["kind"] for p in namespace["pushed"]] == ["models", "tools", "twins"]
    assert {e["type"] for e in namespace["plan"]["create"]} >= {"twin", "device", "processor"}
    telemetry, both = namespace["telemetry"], namespace["both"]
    assert len(telemetry) >= 200 and "Cantilever_Angle_radians" in telemetry.columns
    assert str(telemetry.index.tz) == "UTC" and telemetry.index.is_monotonic_increasing
    assert len(both) > 0 and list(both.columns) == ["Cantilever_Angle_radians", "theta"]
    assert namespace["run"]["state"] == "succeeded", printed.getvalue()
    assert "stream telemetry:" in printed.getvalue()  # the analyze run's log, followed
    assert [item["name"] for item in namespace["diff"]["update"]] == ["fmu"]
    assert "purged: 404" in printed.getvalue()
