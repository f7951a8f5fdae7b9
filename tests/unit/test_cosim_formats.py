"""The co-simulation formats (cosim/maestro.py, ssp.py, yamlform.py): the same
mass-spring-damper pair in each (tests/cosim_files, modelled on files the tools write) reads
into the same System, and bad or hostile files are refused with a message naming the file,
the key or element, and the problem."""

from __future__ import annotations

import json
import zipfile
from pathlib import Path
from typing import Any

import pytest

from twinlink.cosim.maestro import read_maestro
from twinlink.cosim.model import Algorithm, Connection, Constraint, CosimFormatError, Port, System
from twinlink.cosim.ssp import extract, read_ssp
from twinlink.cosim.yamlform import read_yaml, to_yaml
from twinlink.domain.errors import InvalidInputError

FILES = Path(__file__).resolve().parents[1] / "cosim_files"
MSD = FILES / "msd"
SSP_DIR = FILES / "msd_ssp"

M1, M2 = "msd1.msd1i", "msd2.msd2i"
CONNECTIONS = {
    Connection(Port(M1, "x1"), Port(M2, "x1")),
    Connection(Port(M1, "v1"), Port(M2, "v1")),
    Connection(Port(M2, "fk"), Port(M1, "fk")),
}
PARAMETERS = {Port(M2, name): 1.0 for name in ("c2", "cc", "d2", "dc", "m2")}


def make_ssp(path: Path, ssd: str | None = None, extra: dict[str, bytes] | None = None) -> Path:
    """An .ssp archive of tests/cosim_files/msd_ssp (its ssd replaced by `ssd`), with
    placeholder FMUs: reading a system opens no FMU."""
    with zipfile.ZipFile(path, "w") as archive:
        if ssd is None:
            ssd = (SSP_DIR / "SystemStructure.ssd").read_text()
        archive.writestr("SystemStructure.ssd", ssd)
        archive.write(SSP_DIR / "resources" / "msd2.ssv", "resources/msd2.ssv")
        for name in ("MassSpringDamper1.fmu", "MassSpringDamper2.fmu"):
            archive.writestr(f"resources/{name}", b"placeholder")
        for name, data in (extra or {}).items():
            archive.writestr(name, data)
    return path


def ssd_text() -> str:
    return (SSP_DIR / "SystemStructure.ssd").read_text()


def assert_msd(system: System) -> None:
    assert [i.name for i in system.instances] == [M1, M2]
    assert [Path(i.fmu).name for i in system.instances] == [
        "MassSpringDamper1.fmu",
        "MassSpringDamper2.fmu",
    ]
    assert len(system.connections) == len(CONNECTIONS)
    assert set(system.connections) == CONNECTIONS
    assert dict(system.parameters) == PARAMETERS
    assert system.start_time == 0.0
    assert system.end_time == 10.0


# --- the same system in every format


def test_maestro_multimodel_with_its_coe_settings() -> None:
    system = read_maestro(MSD / "mm.json", settings="coe.json")
    assert_msd(system)
    assert system.algorithm == Algorithm("fixed-step", 0.001, master="jacobi")
    assert dict(system.log_variables) == {M2: ("x2", "v2")}
    assert system.source == "maestro"
    assert system.instances[0].fmu == "MassSpringDamper1.fmu"  # as written, relative


def test_maestro2_single_file_and_the_yaml_form_read_the_same_system() -> None:
    maestro = read_maestro(MSD / "maestro2.json")
    yaml = read_yaml(MSD / "msd.yaml")
    assert_msd(maestro)
    assert_msd(yaml)
    assert yaml.source == "yaml"
    # every field but where it came from
    assert {**_fields(maestro), "source": "yaml"} == _fields(yaml)


def test_ssp_archive_reads_the_same_system(tmp_path: Path) -> None:
    system = read_ssp(make_ssp(tmp_path / "msd.ssp"), step_size=0.001)
    assert_msd(system)
    assert [i.fmu for i in system.instances] == [
        "resources/MassSpringDamper1.fmu",
        "resources/MassSpringDamper2.fmu",
    ]
    # the system output x2 only shows msd2's x2: no connection of its own
    assert system.algorithm == Algorithm("fixed-step", 0.001)
    assert system.source == "ssp"
    maestro = read_maestro(MSD / "maestro2.json")
    assert set(system.connections) == set(maestro.connections)
    assert dict(system.parameters) == dict(maestro.parameters)


@pytest.mark.parametrize("fmt", ["maestro", "ssp", "yaml", "var-step"])
def test_every_format_round_trips_through_the_yaml_form(tmp_path: Path, fmt: str) -> None:
    system = {
        "maestro": lambda: read_maestro(MSD / "mm.json", settings="coe.json"),
        "ssp": lambda: read_ssp(make_ssp(tmp_path / "msd.ssp")),
        "yaml": lambda: read_yaml(MSD / "msd.yaml"),
        "var-step": lambda: read_maestro(MSD / "mm.json", settings=MSD / "varstep.json"),
    }[fmt]()
    again = read_yaml("converted.yaml", text=to_yaml(system))
    assert _fields(again) == {**_fields(system), "source": "yaml"}


def test_ssp_step_defaults_to_a_500th_of_the_experiment(tmp_path: Path) -> None:
    system = read_ssp(make_ssp(tmp_path / "msd.ssp"))
    assert system.algorithm.size == pytest.approx(10.0 / 500)


def test_maestro_settings_add_parameters_and_logged_variables() -> None:
    settings = {
        "algorithm": {"type": "fixed-step", "size": 0.01},
        "parameters": {"{msd2}.msd2i.c2": 2.5, "{msd1}.msd1i.c1": 1},
        "logVariables": {"{msd2}.msd2i": ["v2", "fk"], "{msd1}.msd1i": ["x1"]},
    }
    system = read_maestro(MSD / "mm.json", settings=settings)
    assert dict(system.parameters) == {
        **PARAMETERS,
        Port(M2, "c2"): 2.5,
        Port(M1, "c1"): 1,
    }
    assert dict(system.log_variables) == {M2: ("x2", "v2", "fk"), M1: ("x1",)}
    assert system.algorithm.size == 0.01


def test_maestro_var_step_settings_from_maestros_test_file() -> None:
    system = read_maestro(MSD / "mm.json", settings=MSD / "varstep.json")
    bd = Constraint(
        "bd", "boundeddifference", (Port(M1, "x1"), Port(M2, "fk")), abstol=1.0, reltol=1.0
    )
    assert system.algorithm == Algorithm(
        "var-step", 1e-4, min_size=1e-6, max_size=1.0, master="jacobi", constraints=(bd,)
    )


def test_maestro_from_parsed_json_and_legacy_end_time() -> None:
    data = json.loads((MSD / "maestro2.json").read_text())
    del data["endTime"]
    data["end_time"] = 5.0  # the legacy COE's spelling, in Maestro's own test files
    data["aKeyFromANewerTool"] = {"anything": [1, 2]}
    system = read_maestro(data)
    assert system.end_time == 5.0
    assert set(system.connections) == CONNECTIONS


def _fields(system: System) -> dict[str, Any]:
    return {
        "instances": system.instances,
        "connections": system.connections,
        "parameters": dict(system.parameters),
        "log_variables": dict(system.log_variables),
        "algorithm": system.algorithm,
        "start_time": system.start_time,
        "end_time": system.end_time,
        "source": system.source,
    }


# --- Maestro refusals


def maestro_with(**changes: Any) -> dict[str, Any]:
    data: dict[str, Any] = json.loads((MSD / "maestro2.json").read_text())
    for key, value in changes.items():
        if value is None:
            del data[key]
        else:
            data[key] = value
    return data


@pytest.mark.parametrize(
    ("changes", "words"),
    [
        ({"fmus": None}, "fmus: missing or empty"),
        ({"fmus": {"msd1": "a.fmu"}}, "the key 'msd1' is not written \"{key}\""),
        ({"connections": ["{msd1}.msd1i.x1"]}, "connections: is not an object"),
        (
            {"connections": {"{msd1}.msd1i.x1": "{msd2}.msd2i.x1"}},
            "connections.{msd1}.msd1i.x1: is not a list of inputs",
        ),
        ({"connections": {"{msd1}.x1": []}}, "'{msd1}.x1' is not a port"),
        ({"connections": {"{nope}.i.x1": []}}, "the FMU {nope} is not in fmus"),
        ({"parameters": {"{msd2}.msd2i.c2": [1]}}, "parameters.{msd2}.msd2i.c2: [1] is not"),
        ({"logVariables": {"{msd2}.msd2i": "x2"}}, "logVariables.{msd2}.msd2i: is not a list"),
        ({"algorithm": None}, "algorithm: missing"),
        ({"algorithm": {"type": "fixed-step"}}, "algorithm.size: None is not a step size"),
        ({"algorithm": {"type": "fixed-step", "size": -1}}, "algorithm.size: -1 is not"),
        ({"algorithm": {"type": "var-step", "size": 0.1}}, "is not [min, max]"),
        (
            {"algorithm": {"type": "var-step", "size": [0.1, 1], "initsize": 2}},
            "initsize 2.0 is not within size [0.1, 1.0]",
        ),
        ({"algorithm": {"type": "euler", "size": 1}}, "algorithm.type: 'euler' is neither"),
        ({"endTime": "10"}, "endTime: '10' is not a time in seconds"),
        ({"endTime": -1}, "endTime: -1.0 is not after startTime 0.0"),
    ],
)
def test_maestro_wrong_shapes_are_refused_naming_the_key(
    changes: dict[str, Any], words: str
) -> None:
    with pytest.raises(CosimFormatError, match="the multi-model") as err:
        read_maestro(maestro_with(**changes))
    assert words in str(err.value)
    assert isinstance(err.value, InvalidInputError) and err.value.status == 422


def test_maestro_bad_json_is_refused_with_its_line(tmp_path: Path) -> None:
    bad = tmp_path / "mm.json"
    bad.write_text('{\n  "fmus": {\n    "{a}": "a.fmu",\n  }\n}\n')
    with pytest.raises(CosimFormatError, match=r"mm.json: is not valid JSON: .* line 4"):
        read_maestro(bad)
    bad.write_text("[1, 2]")
    with pytest.raises(CosimFormatError, match="is not a JSON object"):
        read_maestro(bad)
    with pytest.raises(CosimFormatError, match="cannot be read"):
        read_maestro(tmp_path / "missing.json")


# --- SSP refusals


def test_ssp_without_a_system_structure_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "empty.ssp"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("resources/a.fmu", b"x")
    with pytest.raises(CosimFormatError, match=r"empty.ssp: the archive has no SystemStructure"):
        read_ssp(path)
    (tmp_path / "plain.ssp").write_text("not a zip")
    with pytest.raises(CosimFormatError, match="is not an SSP archive"):
        read_ssp(tmp_path / "plain.ssp")


@pytest.mark.parametrize(
    "doctype",
    [
        '<!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;&lol;&lol;">]>',
        '<!DOCTYPE x SYSTEM "http://127.0.0.1:9/x.dtd">',
        "<!DOCTYPE x>",
    ],
)
def test_ssp_with_a_doctype_is_refused(tmp_path: Path, doctype: str) -> None:
    text = ssd_text().replace("?>\n", f"?>\n{doctype}\n", 1)
    with pytest.raises(CosimFormatError, match="declares a DTD or an entity, refused"):
        read_ssp(make_ssp(tmp_path / "x.ssp", text))


def test_ssv_with_an_entity_is_refused(tmp_path: Path) -> None:
    ssv = b'<?xml version="1.0"?>\n<!DOCTYPE p [<!ENTITY e SYSTEM "file:///etc/passwd">]>\n<p/>'
    text = ssd_text().replace('source="resources/msd2.ssv"', 'source="resources/evil.ssv"')
    path = make_ssp(tmp_path / "x.ssp", text, {"resources/evil.ssv": ssv})
    with pytest.raises(CosimFormatError, match=r"evil.ssv declares a DTD or an entity"):
        read_ssp(path)


@pytest.mark.parametrize(
    ("old", "new", "words"),
    [
        (
            'source="resources/MassSpringDamper1.fmu"',
            'source="../MassSpringDamper1.fmu"',
            "'../MassSpringDamper1.fmu' is not a path inside the archive",
        ),
        (
            'source="resources/MassSpringDamper1.fmu"',
            'source="/etc/MassSpringDamper1.fmu"',
            "is not a path inside the archive",
        ),
        (
            'source="resources/MassSpringDamper1.fmu"',
            'source="resources/Missing.fmu"',
            "its source resources/Missing.fmu is not in the archive",
        ),
        (
            'endElement="msd1.msd1i" endConnector="fk"',
            'endElement="nobody" endConnector="fk"',
            "'nobody' is not a component of the system",
        ),
        (
            '<ssv:Real value="1.0"/>\n                  </ssv:Parameter>',
            '<ssv:Real value="one"/>\n                  </ssv:Parameter>',
            "ssv:Parameter 'dc': 'one' is not an ssv:Real value",
        ),
        ('stopTime="10.0"', 'stopTime="-1"', "stopTime -1.0 is not after 0.0"),
        ("</ssd:Connections>", "</ssd:Connection>", "is not well-formed XML"),
    ],
)
def test_ssp_bad_elements_are_refused_naming_them(
    tmp_path: Path, old: str, new: str, words: str
) -> None:
    text = ssd_text()
    assert old in text
    with pytest.raises(CosimFormatError) as err:
        read_ssp(make_ssp(tmp_path / "x.ssp", text.replace(old, new, 1)))
    assert words in str(err.value)
    assert "x.ssp" in str(err.value)


def test_ssp_connections_through_a_system_connector_are_joined(tmp_path: Path) -> None:
    # msd1's x1 reaches msd2 through the system's own connector "bus"
    direct = (
        '<ssd:Connection startElement="msd1.msd1i" startConnector="x1" '
        'endElement="msd2.msd2i" endConnector="x1"/>'
    )
    through = (
        '<ssd:Connection startElement="msd1.msd1i" startConnector="x1" endConnector="bus"/>'
        '<ssd:Connection startConnector="bus" endElement="msd2.msd2i" endConnector="x1"/>'
    )
    text = ssd_text().replace(direct, through)
    assert set(read_ssp(make_ssp(tmp_path / "x.ssp", text)).connections) == CONNECTIONS
    # a system input nothing inside feeds would take its value from outside the file
    unfed = ssd_text().replace(
        direct, '<ssd:Connection startConnector="u" endElement="msd2.msd2i" endConnector="x1"/>'
    )
    with pytest.raises(CosimFormatError, match=r"system connector 'u'.*nothing in the system"):
        read_ssp(make_ssp(tmp_path / "y.ssp", unfed))


def test_ssp_nested_systems_are_refused_clearly(tmp_path: Path) -> None:
    text = ssd_text().replace("<ssd:Elements>", '<ssd:Elements><ssd:System name="inner"/>', 1)
    with pytest.raises(CosimFormatError, match="nested ssd:System, not supported"):
        read_ssp(make_ssp(tmp_path / "x.ssp", text))


# --- extract


def test_extract_unpacks_the_archive(tmp_path: Path) -> None:
    path = make_ssp(tmp_path / "msd.ssp")
    written = extract(path, tmp_path / "out")
    assert (tmp_path / "out" / "resources" / "MassSpringDamper1.fmu").read_bytes() == b"placeholder"
    assert (tmp_path / "out" / "SystemStructure.ssd").read_text() == ssd_text()
    assert sorted(p.relative_to(tmp_path / "out").as_posix() for p in written) == [
        "SystemStructure.ssd",
        "resources/MassSpringDamper1.fmu",
        "resources/MassSpringDamper2.fmu",
        "resources/msd2.ssv",
    ]


@pytest.mark.parametrize("name", ["../evil.txt", "/tmp/evil.txt", "resources/../../evil.txt"])
def test_extract_refuses_zip_slip_writing_nothing(tmp_path: Path, name: str) -> None:
    path = make_ssp(tmp_path / "evil.ssp", extra={name: b"gotcha"})
    out = tmp_path / "out" / "deeper"
    with pytest.raises(CosimFormatError, match="is not a path inside the archive"):
        extract(path, out)
    assert not out.exists()  # checked before anything is written
    assert not (tmp_path / "out" / "evil.txt").exists()


def test_extract_refuses_links(tmp_path: Path) -> None:
    path = make_ssp(tmp_path / "link.ssp")
    with zipfile.ZipFile(path, "a") as archive:
        info = zipfile.ZipInfo("resources/link")
        info.external_attr = (0o120777) << 16
        archive.writestr(info, "/etc/passwd")
    with pytest.raises(CosimFormatError, match="'resources/link' is a link, refused"):
        extract(path, tmp_path / "out")


# --- YAML refusals, with lines


@pytest.mark.parametrize(
    ("old", "new", "words"),
    [
        ("end_time: 10", "end_tim: 10", "line 22, column 1: end_tim: unknown key"),
        ("  msd1.msd1i.v1: [msd2.msd2i.v1]", "  msd1.msd1i.v1: [msd3.x.v1]", "line 7"),
        ("  size: 0.001", "  size: 0", "line 19, column 3: algorithm.size: 0 is not a step"),
        ("  master: jacobi", "  master: newton", "'newton' is not \"jacobi\""),
        ("  msd2.msd2i: [x2, v2]", "  msd9: [x2, v2]", "log.msd9: is not a declared instance"),
        ("  msd2.msd2i.c2: 1.0", "  msd2.msd2i.c2: [1.0]", "line 10, column 3: parameters"),
        ("start_time: 0", "start_time: 0\nstart_time: 1", "line 22"),
        ("  type: fixed-step", "  type: fixed-step\n  tolerance: 1", "algorithm.tolerance"),
    ],
)
def test_yaml_mistakes_are_refused_with_their_line(
    tmp_path: Path, old: str, new: str, words: str
) -> None:
    text = (MSD / "msd.yaml").read_text()
    assert old in text
    path = tmp_path / "cosim.yaml"
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(CosimFormatError) as err:
        read_yaml(path)
    assert words in str(err.value)
    assert str(path) in str(err.value)


def test_yaml_syntax_error_and_wrong_top_level(tmp_path: Path) -> None:
    with pytest.raises(
        CosimFormatError, match=r"x.yaml: line 3, column 1: while parsing a flow sequence"
    ):
        read_yaml("x.yaml", text="instances:\n  a: [b\n")
    with pytest.raises(CosimFormatError, match="is not a mapping"):
        read_yaml("x.yaml", text="- 1\n")
    with pytest.raises(CosimFormatError, match="holds 2 YAML documents; write one"):
        read_yaml("x.yaml", text="a: 1\n---\nb: 2\n")
    with pytest.raises(CosimFormatError, match="instances and algorithm are required"):
        read_yaml("x.yaml", text="instances: {a: a.fmu}\n")


def test_yaml_ports_split_at_the_longest_instance_name() -> None:
    text = (
        "instances: {a: a.fmu, a.b: b.fmu}\n"
        "connections: {a.b.y: a.u.v, a.y: [a.b.u]}\n"
        "algorithm: {type: var-step, size: 0.1, min_size: 0.01, max_size: 1}\n"
    )
    system = read_yaml("x.yaml", text=text)
    assert system.connections == (
        Connection(Port("a.b", "y"), Port("a", "u.v")),
        Connection(Port("a", "y"), Port("a.b", "u")),
    )
    assert system.algorithm == Algorithm("var-step", 0.1, 0.01, 1.0, "gauss-seidel")
