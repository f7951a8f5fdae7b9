"""The real `twinlink` command, run as a subprocess against a real server."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import click
import pytest
import yaml
from click.testing import CliRunner

from tests.conftest import ROOT, Server, free_port
from tests.integration._util import (
    CRANE_SLUG,
    HALL_SLUG,
    ILMATAR,
    apply,
    load_yaml,
    twin_doc,
    unique,
)

pytestmark = pytest.mark.integration

CLI = [sys.executable, "-m", "twinlink"]


@dataclass
class Result:
    args: list[str]
    code: int
    out: str
    err: str

    def ok(self) -> Result:
        assert self.code == 0, f"twinlink {' '.join(self.args)} -> {self.code}\n{self.err}"
        assert "Traceback" not in self.err
        return self


def _env(config_home: Path, **overrides: str | None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("TWINLINK_")}
    env["XDG_CONFIG_HOME"] = str(config_home)
    env["HOME"] = str(config_home)  # nothing may fall back to the real home's config
    env["NO_COLOR"] = "1"
    for k, v in overrides.items():
        if v is not None:
            env[k] = v
    return env


def _start(args: list[str], env: dict[str, str], stdin: str | None) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [*CLI, *args],
        env=env,
        cwd=ROOT,
        text=True,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        stdin=subprocess.PIPE if stdin is not None else subprocess.DEVNULL,
    )


def _finish(p: subprocess.Popen[str], args: list[str], stdin: str | None) -> Result:
    out, err = p.communicate(stdin, timeout=120)
    return Result(args, p.returncode, out, err)


class Cli:
    def __init__(self, server: Server, config_home: Path) -> None:
        self.server = server
        self.config_home = config_home

    def env(self, token: bool = True, url: bool = True) -> dict[str, str]:
        return _env(
            self.config_home,
            TWINLINK_URL=self.server.url if url else None,
            TWINLINK_TOKEN=self.server.admin_token if token else None,
        )

    def __call__(
        self, *args: str, token: bool = True, url: bool = True, stdin: str | None = None
    ) -> Result:
        return _finish(_start(list(args), self.env(token, url), stdin), list(args), stdin)

    def many(self, *commands: list[str]) -> list[Result]:
        """Independent commands, run at the same time (each one is a Python start-up)."""
        procs = [(_start(c, self.env(), None), c) for c in commands]
        return [_finish(p, c, None) for p, c in procs]


@pytest.fixture(scope="module")
def cli(server: Server, tmp_path_factory: pytest.TempPathFactory) -> Cli:
    return Cli(server, tmp_path_factory.mktemp("config"))


@pytest.fixture(scope="module")
def applied(cli: Cli) -> Result:
    return cli("apply", "-f", str(ILMATAR) + "/").ok()


def test_apply_a_folder_then_list(cli: Cli, applied: Result) -> None:
    lines = applied.out.splitlines()
    # One line per document: the hall, then the crane's three parts (files in name order).
    assert len(lines) == len(list(ILMATAR.glob("*.yaml")))
    assert any(line.startswith(f"twin/{HALL_SLUG} created") for line in lines)
    assert any(line.startswith(f"twin/{CRANE_SLUG} created") for line in lines)
    listed = cli("twins", "ls").ok()
    slugs = [line.split()[0] for line in listed.out.splitlines()]
    assert CRANE_SLUG in slugs and HALL_SLUG in slugs
    again = cli("apply", "-f", str(ILMATAR)).ok()
    assert all(" unchanged " in line for line in again.out.splitlines()), again.out


def test_twins_get_prints_the_document(cli: Cli, applied: Result) -> None:
    public = load_yaml(ILMATAR / "ilmatar-public.yaml")
    as_json, as_yaml = cli.many(
        ["twins", "get", CRANE_SLUG, "-o", "json"], ["twins", "get", CRANE_SLUG]
    )
    doc = json.loads(as_json.ok().out)
    assert doc["name"] == public["name"]
    assert doc["id"] == public["id"]
    assert yaml.safe_load(as_yaml.ok().out) == doc


def test_search_prints_the_crane(cli: Cli, applied: Result) -> None:
    result = cli("search", "CAD").ok()
    first = result.out.splitlines()[0]
    assert first.split()[0] == CRANE_SLUG
    [cad_feature] = [
        f["name"]
        for f in load_yaml(ILMATAR / "ilmatar-public.yaml")["features"]
        if "CAD" in f.get("keywords", [])
    ]
    assert cad_feature in first


def test_twins_tree_and_rm(cli: Cli, applied: Result) -> None:
    tree = cli("twins", "tree", HALL_SLUG).ok()
    lines = tree.out.splitlines()
    assert lines[0].startswith(HALL_SLUG)
    assert lines[1].strip().startswith(CRANE_SLUG) and lines[1].startswith("  ")
    slug = unique("doomed")
    with cli.server.admin as admin:
        apply(admin, twin_doc(f"urn:test:{slug}", name="Doomed"))
    assert slug in cli("twins", "rm", slug).ok().out
    gone = cli("twins", "get", slug)
    assert gone.code != 0


def _commands() -> list[list[str]]:
    from twinlink.cli import main

    def walk(cmd: click.Command, path: list[str]) -> Iterator[list[str]]:
        yield path
        if isinstance(cmd, click.Group):
            for name, sub in sorted(cmd.commands.items()):
                yield from walk(sub, [*path, name])

    return list(walk(main, []))


def test_help_works_for_every_command(cli: Cli) -> None:
    commands = _commands()
    documented = [
        ["up"],
        ["demo"],
        ["apply"],
        ["login"],
        ["search"],
        ["twins", "ls"],
        ["twins", "get"],
        ["twins", "rm"],
        ["twins", "tree"],
        ["users", "ls"],
        ["users", "add"],
        ["users", "set"],
        ["users", "rm"],
        ["tokens", "ls"],
        ["tokens", "create"],
        ["tokens", "revoke"],
    ]
    for c in documented:
        assert c in commands, f"twinlink {' '.join(c)} is missing"
    # In this process, with click's runner: a Python start-up for each of the 60 commands took
    # a minute. The environment is the other tests' (the config home, the server's URL).
    from twinlink.cli import main

    runner = CliRunner()
    env = {**{k: None for k in os.environ if k.startswith("TWINLINK_")}, **cli.env()}
    for c in commands:
        r = runner.invoke(main, [*c, "--help"], prog_name="twinlink", env=env)
        assert (r.exit_code, r.exception) == (0, None), f"twinlink {' '.join(c)} --help: {r}"
        assert r.stdout.startswith(f"Usage: {' '.join(['twinlink', *c])} "), r.stdout[:200]
        assert r.stderr == ""


def test_error_exits_non_zero_with_a_clear_message(cli: Cli) -> None:
    missing = unique("no-such-twin")
    r = cli("twins", "get", missing)
    assert r.code != 0
    assert r.err.startswith("Error: "), r.err  # click's own style, as for usage errors
    assert missing in r.err and "404" in r.err
    assert "Traceback" not in r.err + r.out
    assert r.out == ""


def test_unreachable_server_and_missing_token_are_explained(cli: Cli, tmp_path: Path) -> None:
    closed = f"http://127.0.0.1:{free_port()}"
    env = _env(tmp_path, TWINLINK_URL=closed, TWINLINK_TOKEN="tl_whatever")
    p = _start(["twins", "ls"], env, None)
    unreachable = _finish(p, ["twins", "ls"], None)
    p = _start(["twins", "ls"], _env(tmp_path, TWINLINK_URL=cli.server.url), None)
    no_token = _finish(p, ["twins", "ls"], None)  # a config home without a saved login
    for r in (unreachable, no_token):
        assert r.code != 0
        assert "Traceback" not in r.err + r.out
    assert "cannot reach" in unreachable.err
    assert "401" in no_token.err and "login" in no_token.err


def test_malformed_yaml_file_prints_the_line(cli: Cli, tmp_path: Path) -> None:
    bad = tmp_path / "broken.yaml"
    # Line 4 indents a key under the plain value of line 3: "mapping values are not allowed".
    bad.write_text('version: "1.0"\nprivacy: public\nname: Broken\n  oops: indented\n')
    good = tmp_path / "good.yaml"
    good.write_text(twin_doc(f"urn:test:{unique('good')}", name="Good one"))
    r = cli("apply", "-f", str(bad))
    assert r.code != 0
    assert "Traceback" not in r.err + r.out
    assert str(bad) in r.err
    assert "line 4" in r.err, r.err
    both = cli("apply", "-f", str(good), "-f", str(bad))
    assert both.code != 0
    assert "created" in both.out


def test_login_saves_credentials_for_later_commands(cli: Cli, applied: Result) -> None:
    r = cli("login", "-u", "admin", "-p", cli.server.admin_password, token=False).ok()
    saved = cli.config_home / "twinlink" / "credentials.json"
    assert str(saved) in r.out
    assert stat.S_IMODE(saved.stat().st_mode) == 0o600
    assert cli.server.admin_password not in saved.read_text()
    listed = cli("twins", "ls", token=False).ok()  # the saved token, no TWINLINK_TOKEN
    assert CRANE_SLUG in listed.out
    no_url = cli("twins", "ls", token=False, url=False).ok()  # the saved URL too
    assert CRANE_SLUG in no_url.out
    wrong = cli("login", "-u", "admin", "-p", "not-the-password", token=False)
    assert wrong.code != 0 and "401" in wrong.err and "Traceback" not in wrong.err


def test_tokens_create_prints_a_working_token(cli: Cli) -> None:
    name = unique("ci")
    r = cli("tokens", "create", name).ok()
    token = r.out.strip()
    assert token.startswith("tl_") and "\n" not in token
    with cli.server.client(token) as c:
        me = c.get("/api/v1/auth/me")
    assert me.status_code == 200 and me.json()["username"] == "admin"
    listed = cli("tokens", "ls").ok()
    assert name in listed.out and token not in listed.out
    # The admin token the command sends is marked; the new one is not.
    marked = [line for line in listed.out.splitlines() if line.endswith("(this token)")]
    assert len(marked) == 1 and "bootstrap" in marked[0]
    everyone = cli("tokens", "ls", "--all").ok()
    [new_line] = [line for line in everyone.out.splitlines() if name in line]
    assert new_line.split()[2] == "admin"
    token_id = next(line.split()[0] for line in listed.out.splitlines() if name in line)
    cli("tokens", "revoke", token_id).ok()
    with cli.server.client(token) as c:
        assert c.get("/api/v1/auth/me").status_code == 401


def test_users_add_ls_set_rm(cli: Cli) -> None:
    cli("users", "add", "bob", "--password", "bobs-password-1", "-g", "crew").ok()
    listed = cli("users", "ls").ok()
    [bob] = [line for line in listed.out.splitlines() if line.split()[0] == "bob"]
    assert "crew" in bob
    with cli.server.client() as c:
        r = c.post("/api/v1/auth/login", json={"username": "bob", "password": "bobs-password-1"})
        assert r.status_code == 200
        cli("users", "set", "bob", "--disable").ok()
        r = c.post("/api/v1/auth/login", json={"username": "bob", "password": "bobs-password-1"})
        assert r.status_code == 401
    cli("users", "rm", "bob").ok()
    with cli.server.admin as admin:
        users = [u["username"] for u in admin.get("/api/v1/users").json()["users"]]
    assert "bob" not in users
    again = cli("users", "rm", "bob")
    assert again.code != 0 and "Traceback" not in again.err and "bob" in again.err


def test_devices_ls_says_which_devices_are_connected(cli: Cli) -> None:
    from tests.integration._live import device_socket, device_twin, receive

    slug, (token,) = device_twin(cli.server)
    cli("devices", "add", slug, "spare").ok()
    assert "never seen" in cli("devices", "ls", slug).ok().out
    with device_socket(cli.server, token) as ws:
        receive(ws, "welcome")
        listed = {
            line.split()[0]: line for line in cli("devices", "ls", slug).ok().out.splitlines()
        }
    assert "connected" in listed["dev0"] and "never seen" in listed["spare"]


def test_help_lists_every_command_whole_on_an_80_column_terminal(cli: Cli) -> None:
    groups = [c for c in _commands() if len(c) <= 1]  # the root and each top-level command
    env = {**cli.env(), "COLUMNS": "80"}
    procs = [(_start([*g, "--help"], env, None), g) for g in groups]
    for proc, group in procs:
        out = _finish(proc, [*group, "--help"], None).ok().out
        listed = out.split("\nCommands:\n", 1)
        if len(listed) == 2:  # a group: no summary may be cut off with "..."
            cut = [line for line in listed[1].splitlines() if line.endswith("...")]
            assert not cut, f"twinlink {' '.join(group)} --help:\n{out}"


def test_lists_have_a_header_row(cli: Cli) -> None:
    from tests.integration._live import device_twin

    slug, _ = device_twin(cli.server)
    with cli.server.admin as admin:
        body = {"name": "echo", "base_url": "http://127.0.0.1:9/api/"}
        assert admin.post(f"/api/v1/twins/{slug}/services", json=body).status_code == 201
        body = {"name": "logger", "kind": "udp", "config": {"port": 0, "format": "json"}}
        assert admin.post(f"/api/v1/twins/{slug}/connectors", json=body).status_code == 201
    cli("processors", "create", slug, "smooth", "lowpass", "-p", 'signals=["x"]', "-p",
        "cutoff_hz=2", "-p", "sample_rate_hz=100", "--stopped").ok()  # fmt: skip
    processors, services, connectors, devices = cli.many(
        ["processors", "ls", slug],
        ["services", "ls", slug],
        ["connectors", "ls", slug],
        ["devices", "ls", slug],
    )
    tables = {
        "processors": (processors, ["NAME", "BLUEPRINT", "STATE", "STREAMS"], "smooth"),
        "services": (services, ["NAME", "SOURCE", "AUTH", "HEALTH", "BASE", "URL"], "echo"),
        "connectors": (connectors, ["NAME", "KIND", "DEVICE", "STATE", "MESSAGES"], "logger"),
        "devices": (devices, ["NAME", "TOKEN", "SEEN", "DESCRIPTION"], "dev0"),
    }
    for what, (result, header, first) in tables.items():
        lines = result.ok().out.splitlines()
        assert lines[0].split()[: len(header)] == header, (what, result.out)
        assert lines[1].split()[0] == first, (what, result.out)
        # The columns line up: each row's second cell starts where the header's does.
        column = lines[0].index(header[1])
        assert lines[1][column - 2 : column] == "  " and lines[1][column] != " ", lines


def test_floats_are_printed_at_a_readable_precision(cli: Cli) -> None:
    from tests.integration._live import batch, device_socket, device_twin, receive, send

    slug, (token,) = device_twin(cli.server)
    with device_socket(cli.server, token) as ws:
        receive(ws, "welcome")
        send(ws, batch(1, [{"time": 1_700_000_000_000_000_000, "values": {"x": 0.123456789012}}]))
        assert receive(ws, "ack")["seq"] == 1
    latest = cli("history", "latest", slug, "telemetry").ok().out.splitlines()
    assert latest[1].split()[-1] == "0.123457"
    whole = json.loads(cli("history", "latest", slug, "telemetry", "--json").ok().out)
    assert whole["values"]["x"]["value"] == 0.123456789012


def test_services_call_indents_json_on_a_terminal_and_passes_bytes_through_a_pipe(
    cli: Cli,
) -> None:
    import hashlib
    import pty

    from tests.integration._upstream import Upstream
    from tests.integration._upstream_answers import download_digest

    upstream = Upstream().start()
    try:
        slug = unique("call")
        with cli.server.admin as admin:
            apply(admin, twin_doc(f"urn:{slug}", name="Callee", slug=slug))
            body = {"name": "up", "base_url": upstream.base("open")}
            assert admin.post(f"/api/v1/twins/{slug}/services", json=body).status_code == 201
        piped = subprocess.run(
            [*CLI, "services", "call", slug, "up", "bytes/100000"],
            env=cli.env(), cwd=ROOT, capture_output=True, timeout=120,
        )  # fmt: skip
        assert piped.returncode == 0, piped.stderr
        assert hashlib.sha256(piped.stdout).hexdigest() == download_digest(100_000)
        as_json = subprocess.run(
            [*CLI, "services", "call", slug, "up", "echo/x"],
            env=cli.env(), cwd=ROOT, capture_output=True, timeout=120,
        )  # fmt: skip
        assert b"\n" not in as_json.stdout.rstrip(b"\n")  # as the service sent it
        assert json.loads(as_json.stdout)["method"] == "GET"
        controller, terminal = pty.openpty()
        with subprocess.Popen(
            [*CLI, "services", "call", slug, "up", "echo/x"],
            env=cli.env(), cwd=ROOT, stdout=terminal, stderr=subprocess.PIPE,
        ) as proc:  # fmt: skip
            os.close(terminal)
            shown = b""
            while True:
                try:
                    chunk = os.read(controller, 65536)
                except OSError:  # the terminal closed: the command has ended
                    break
                if not chunk:
                    break
                shown += chunk
            assert proc.wait(timeout=120) == 0
        os.close(controller)
        text = shown.decode().replace("\r\n", "\n")
        assert text.startswith('{\n  "method": "GET"'), text[:200]
        assert json.loads(text)["method"] == "GET"
    finally:
        upstream.stop()
