"""The worker's start: a blueprint built from the server's first frame."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import FmuFiles
from twinlink.processors.blueprint import Batch
from twinlink.processors.worker import build

pytestmark = pytest.mark.integration


def test_an_fmu_starts_in_a_data_dir_given_as_a_relative_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, fmu_files: FmuFiles
) -> None:
    # `make demo` keeps its data in ./.twinlink-demo; FMUs need their resources as a file URI.
    monkeypatch.chdir(tmp_path)
    Path("data/fmus/1").mkdir(parents=True)
    shutil.copy(fmu_files("tingen"), "data/fmus/1/T.fmu")
    init = {
        "ref": {"entry": "twinlink.processors.blueprints.fmu:FmuBlueprint"},
        "processor": "sim",
        "twin": "tingen",
        "params": {"fmu": "T.fmu", "outputs": ["theta"]},
        "inputs": {},
        "rates": {},
        "files": "data/fmus/1",
        "workdir": "data/processors/1",
    }
    runtime, _ = build(init)
    try:
        _, out = runtime.feed(Batch.of([0, 10**6], F=np.array([0.0, 1.0])))
        assert out is not None and out.columns.keys() == {"theta"}
        assert runtime.blueprint.ctx.workdir.is_absolute()
    finally:
        runtime.blueprint.stop()
