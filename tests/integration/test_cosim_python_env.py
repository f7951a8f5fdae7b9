"""Python FMUs that bring their own packages in a co-simulation: an instance's
python_requirements build a virtualenv its isolated process runs in (kinds.py, fmuenv.py),
locally and on a server, where asking for packages needs the right to send FMUs. Split from
test_cosim_kinds.py: these tests install from the package index."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import zipfile
from dataclasses import replace
from pathlib import Path

import pytest

from tests.conftest import start_server, stop_server
from tests.integration._util import assert_problem, make_user, poll_until, unique
from twinlink.cosim.model import Instance, Port
from twinlink.cosim.session import Session
from twinlink.cosim.slaves import CosimRunError
from twinlink.cosim.yamlform import read_yaml
from twinlink.domain.errors import InvalidInputError

pytestmark = pytest.mark.integration


TRIPLER = Path(__file__).parents[1] / "fmus" / "python_tripler" / "Tripler.py"
REQUIREMENT = "more-itertools==10.7.0"  # what Tripler imports; the server has it not


@pytest.fixture(scope="module")
def tripler(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Tripler.fmu (pythonfmu: y = 2 x + 3, importing more_itertools), built with a stand-in
    more_itertools on its path: the FMU carries only the model's source."""
    assert importlib.util.find_spec("more_itertools") is None, "the server has more_itertools"
    folder = tmp_path_factory.mktemp("tripler")
    (folder / "stub").mkdir()
    (folder / "stub" / "more_itertools.py").write_text("def ilen(items): return len(items)\n")
    subprocess.run(
        [sys.executable, "-m", "pythonfmu", "build", "-f", str(TRIPLER), "-d", str(folder)],
        check=True, env={**os.environ, "PYTHONPATH": str(folder / "stub")}, capture_output=True,
    )  # fmt: skip
    return folder / "Tripler.fmu"


TRIPLER_YAML = f"""\
instances:
  t: {{fmu: Tripler.fmu, python_requirements: ["{REQUIREMENT}"]}}
log:
  t: [y]
algorithm: {{type: fixed-step, size: 0.5}}
end_time: 2
"""


def test_a_python_fmu_gets_the_packages_it_needs_in_an_environment_of_its_own(
    tripler: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The YAML form's python_requirements: the instance runs in a process whose Python is a
    virtualenv with more_itertools, installed by pip from the package index; without them the
    FMU's import fails the run, naming the instance and the missing module."""
    monkeypatch.setenv("TWINLINK_FMU_ENVS_DIR", str(tmp_path / "envs"))
    system = read_yaml("t.yaml", text=TRIPLER_YAML)
    assert system.instances == (Instance("t", "Tripler.fmu", True, (REQUIREMENT,)),)
    x = Port("t", "x")
    with Session(system, {"Tripler.fmu": tripler}, external_inputs=[x]) as session:
        rows = [session.initialize()]
        for value in (1.0, 2.0, 4.0, 0.5):
            session.set_inputs({x: value})
            row = session.step()
            assert row is not None
            rows.append(row)
    assert [row[1] for row in rows[1:]] == [5.0, 7.0, 11.0, 4.0]  # 2 x + len("abc")
    (env,) = [p for p in (tmp_path / "envs").iterdir() if p.is_dir()]
    assert (env / "ready").is_file()  # built once, kept for the next run
    plain = replace(system, instances=(Instance("t", "Tripler.fmu"),))
    with pytest.raises(CosimRunError, match="instance 't'") as err:
        Session(plain, {"Tripler.fmu": tripler}, external_inputs=[x])
    assert "more_itertools" in str(err.value)


def test_a_requirement_pip_cannot_install_fails_naming_the_instance(
    tripler: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("TWINLINK_FMU_ENVS_DIR", str(tmp_path / "envs"))
    monkeypatch.setenv("PIP_NO_INDEX", "1")  # nothing to install from: fails at once
    text = TRIPLER_YAML.replace(REQUIREMENT, "twinlink-no-such-package==1.0")
    with pytest.raises(CosimRunError) as err:
        Session(read_yaml("t.yaml", text=text), {"Tripler.fmu": tripler})
    message = str(err.value)
    assert message.startswith(
        "instance 't': its Python environment (twinlink-no-such-package==1.0) could not be "
        "built: pip install failed"
    )
    assert "No matching distribution found for twinlink-no-such-package==1.0" in message


@pytest.mark.parametrize(
    ("entry", "message"),
    [
        ('{fmu: t.fmu, python_requirements: "a==1"}', "is not a list of requirements"),
        ("{fmu: t.fmu, python_requirements: [-r /etc/passwd]}", "pip options and files"),
    ],
)
def test_the_yaml_form_refuses_wrong_python_requirements(entry: str, message: str) -> None:
    text = TRIPLER_YAML.replace(
        f'{{fmu: Tripler.fmu, python_requirements: ["{REQUIREMENT}"]}}', entry
    )
    with pytest.raises(InvalidInputError, match=message):
        read_yaml("t.yaml", text=text)


def test_only_those_who_may_send_fmus_may_ask_the_server_for_packages(
    tmp_path_factory: pytest.TempPathFactory, tripler: Path
) -> None:
    """pip runs the code of the packages it installs: a co-simulation asking for
    python_requirements needs the right native code needs (admins, by default), and is
    refused before anything is resolved or built. An admin's runs on the server, its
    environment built in the data dir's fmu-envs (shared with the FMU processors)."""
    data_dir = tmp_path_factory.mktemp("data")
    server = start_server(data_dir)
    try:
        token = make_user(server, unique("modeller"))
        yaml_headers = {"Content-Type": "application/yaml"}
        with server.admin as admin, server.client(token) as user:
            r = user.post("/api/v1/cosims", content=TRIPLER_YAML.encode(), headers=yaml_headers)
            body = assert_problem(r, 403)
            assert body["detail"].startswith(
                "the upload holds python_requirements, packages pip would install"
            )
            # an admin passes the check: the FMU itself is then looked for (and not found)
            r = admin.post("/api/v1/cosims", content=TRIPLER_YAML.encode(), headers=yaml_headers)
            assert "Tripler.fmu" in assert_problem(r, 422)["detail"]
            # with its FMU beside it, it runs: x stays 0, so each step gives y = 2 x + 3 = 3
            folder = tmp_path_factory.mktemp("upload") / "t.zip"
            with zipfile.ZipFile(folder, "w") as z:
                z.writestr("t.yaml", TRIPLER_YAML)
                z.write(tripler, "Tripler.fmu")
            r = admin.post("/api/v1/cosims", content=folder.read_bytes(),
                           headers={"Content-Type": "application/zip"})  # fmt: skip
            assert r.status_code == 201, r.text
            cosim = f"/api/v1/cosims/{r.json()['id']}"
            assert admin.post(f"{cosim}/start").status_code == 200

            def ended() -> dict[str, object] | None:
                view: dict[str, object] = admin.get(cosim).json()
                return view if view["state"] not in ("created", "running") else None

            view = poll_until(ended, "the co-simulation to end", timeout_s=300)
            assert view["state"] == "finished", view
            rows = admin.get(f"{cosim}/results").json()
            assert rows["data"][rows["columns"].index("t.y")][1:] == [3.0] * 4, rows
            envs = [p for p in (data_dir / "fmu-envs").iterdir() if (p / "ready").is_file()]
            assert len(envs) == 1, list((data_dir / "fmu-envs").iterdir())
    finally:
        stop_server(server)
