"""The FMU builder: reproducible zips, the FMI layout, and clear errors from gcc."""

from __future__ import annotations

import os
import shutil
import stat
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from tests.conftest import FMU_SOURCES, FmuFiles
from twinlink.processors.fmubuild import FmuBuildError, build_fmu, build_if_stale, main

pytestmark = pytest.mark.integration


def copy_sources(name: str, dest: Path) -> Path:
    """A copy of an FMU's source folder (symbolic links copied as the files they point to)."""
    shutil.copytree(FMU_SOURCES[name], dest)
    return dest


@pytest.mark.parametrize("name", ["tingen", "tingen3"])
def test_a_build_elsewhere_gives_identical_bytes(
    fmu_files: FmuFiles, name: str, tmp_path: Path
) -> None:
    # The session's build comes from the repository; this one from a copy in another folder,
    # with warnings made errors (which changes nothing in the output, but fails on a warning).
    src = copy_sources(name, tmp_path / "some" / "other" / "folder")
    again = build_fmu(src, tmp_path / "again.fmu", extra_cflags=["-Werror"])
    assert again.read_bytes() == fmu_files(name).read_bytes()


@pytest.mark.parametrize(
    ("name", "binary", "sources"),
    [
        ("tingen", "binaries/linux64/tingen.so", ["sources/cantilever.h", "sources/tingen.c"]),
        (
            "tingen3",
            "binaries/x86_64-linux/tingen.so",
            ["sources/cantilever.h", "sources/tingen.c"],
        ),
        ("crash", "binaries/linux64/crash.so", ["sources/crash.c", "sources/fmi2cs.h"]),
    ],
)
def test_the_zip_has_the_fmi_layout(
    fmu_files: FmuFiles, name: str, binary: str, sources: list[str]
) -> None:
    path = fmu_files(name)
    with zipfile.ZipFile(path) as zf:
        infos = zf.infolist()
        names = [info.filename for info in infos]
        assert names == sorted(["modelDescription.xml", binary, *sources])
        for info in infos:
            assert info.date_time == (1980, 1, 1, 0, 0, 0)
            assert info.compress_type == zipfile.ZIP_DEFLATED
            mode = stat.S_IMODE(info.external_attr >> 16)
            assert mode == (0o755 if info.filename == binary else 0o644)
        assert (
            zf.read("modelDescription.xml")
            == (FMU_SOURCES[name] / "modelDescription.xml").read_bytes()
        )
        library = zf.read(binary)
    assert library.startswith(b"\x7fELF")
    # Nothing of this machine's folders is baked into the binary.
    assert str(FMU_SOURCES[name]).encode() not in library
    assert str(Path(sys.prefix)).encode() not in library


def test_a_shared_header_is_packed_through_its_link(fmu_files: FmuFiles) -> None:
    header = FMU_SOURCES["tingen"] / "cantilever.h"
    assert header.is_symlink()
    with zipfile.ZipFile(fmu_files("tingen")) as zf:
        assert zf.read("sources/cantilever.h") == header.read_bytes()


def test_a_c_syntax_error_raises_with_gccs_message(tmp_path: Path) -> None:
    src = copy_sources("status", tmp_path / "src")
    (src / "broken.c").write_text("int broken(void) { return 1 + ; }\n")
    with pytest.raises(FmuBuildError) as caught:
        build_fmu(src, tmp_path / "out.fmu")
    message = str(caught.value)
    assert "broken.c:1" in message
    assert "expected expression before ';' token" in message
    assert not (tmp_path / "out.fmu").exists()
    assert list(tmp_path.glob(".out.fmu.*")) == []


def test_a_missing_compiler_says_to_install_one(tmp_path: Path) -> None:
    with pytest.raises(FmuBuildError, match="not found; install it"):
        build_fmu(FMU_SOURCES["status"], tmp_path / "out.fmu", compiler="no-such-cc-for-twinlink")


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (('fmiVersion="2.0"', 'fmiVersion="1.0"'), 'fmiVersion "1.0" is not supported'),
        (('modelIdentifier="status"', 'modelIdentifier="../evil"'), "not a valid C identifier"),
        (("<CoSimulation", "<Nothing"), "neither <CoSimulation> nor <ModelExchange>"),
    ],
)
def test_an_unusable_model_description_is_refused(
    tmp_path: Path, edit: tuple[str, str], message: str
) -> None:
    src = copy_sources("status", tmp_path / "src")
    xml = src / "modelDescription.xml"
    old, new = edit
    xml.write_text(xml.read_text().replace(old, new))
    with pytest.raises(FmuBuildError, match=message):
        build_fmu(src, tmp_path / "out.fmu")


def test_interfaces_with_different_identifiers_are_refused(tmp_path: Path) -> None:
    src = copy_sources("status", tmp_path / "src")
    xml = src / "modelDescription.xml"
    xml.write_text(
        xml.read_text().replace(
            '<CoSimulation modelIdentifier="status"',
            '<ModelExchange modelIdentifier="other"/>\n  <CoSimulation modelIdentifier="status"',
        )
    )
    with pytest.raises(FmuBuildError, match="different modelIdentifiers"):
        build_fmu(src, tmp_path / "out.fmu")


def test_build_if_stale_rebuilds_only_when_a_source_is_newer(tmp_path: Path) -> None:
    src = copy_sources("status", tmp_path / "src")
    out = tmp_path / "status.fmu"
    sources_time = 1_000_000_000  # 2001
    for path in src.iterdir():
        os.utime(path, (sources_time, sources_time))

    assert build_if_stale(src, out) == out  # missing: built
    built_time = sources_time + 100
    os.utime(out, (built_time, built_time))

    build_if_stale(src, out)
    assert out.stat().st_mtime_ns == built_time * 10**9  # up to date: left alone

    os.utime(src / "status.c", (built_time + 1, built_time + 1))
    build_if_stale(src, out)
    assert out.stat().st_mtime_ns != built_time * 10**9  # a newer source: rebuilt
    assert zipfile.ZipFile(out).testzip() is None


def test_the_command_line_prints_the_path(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "status.fmu"
    assert main([str(FMU_SOURCES["status"]), str(out)]) == 0
    assert capsys.readouterr().out.strip() == str(out)
    assert zipfile.is_zipfile(out)

    # --if-stale leaves an up-to-date file alone (its time is set ahead of every source).
    ahead = out.stat().st_mtime_ns + 10**12
    os.utime(out, ns=(ahead, ahead))
    assert main([str(FMU_SOURCES["status"]), str(out), "--if-stale"]) == 0
    assert capsys.readouterr().out.strip() == str(out)
    assert out.stat().st_mtime_ns == ahead

    src = copy_sources("status", tmp_path / "src")
    (src / "status.c").write_text("this is not C\n")
    assert main([str(src), str(tmp_path / "broken.fmu")]) == 1
    assert "error: gcc failed" in capsys.readouterr().err


def test_the_module_runs_as_a_program(tmp_path: Path) -> None:
    out = tmp_path / "status.fmu"
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "twinlink.processors.fmubuild",
            str(FMU_SOURCES["status"]),
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == str(out)
    assert zipfile.is_zipfile(out)


@pytest.mark.parametrize(
    "name",
    [
        *("crash", "leak", "status", "msd_mass", "msd_spring", "ticks"),
        *("incubator_plant", "incubator_controller", "incubator_kalman", "chain_mass"),
    ],
)
def test_the_test_fmus_compile_without_warnings(name: str, tmp_path: Path) -> None:
    build_fmu(FMU_SOURCES[name], tmp_path / f"{name}.fmu", extra_cflags=["-Werror"])
