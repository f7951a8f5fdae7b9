"""Settings from `TWINLINK_*` environment variables or a TOML file.

Precedence, highest first: explicit arguments (CLI flags), environment variables,
the TOML file named by `TWINLINK_CONFIG` (or `--config`), then the defaults below.
Every field is documented in docs/config.md; a test keeps the two in step.
"""

from __future__ import annotations

import os
import tomllib
from pathlib import Path
from typing import Any, Literal
from urllib.parse import urlsplit

from pydantic import Field, SecretStr, ValidationError, field_validator, model_validator
from pydantic_settings import (
    BaseSettings,
    PydanticBaseSettingsSource,
    SettingsConfigDict,
    TomlConfigSettingsSource,
)

from twinlink.domain.backend_urls import check_store_url, kafka_bootstrap, shown_store_url
from twinlink.domain.errors import TwinlinkError


class ConfigError(TwinlinkError, ValueError):
    """Settings that cannot be used; the message names the setting and the problem."""


class Settings(BaseSettings):
    model_config = SettingsConfigDict(env_prefix="TWINLINK_", extra="forbid")

    host: str = Field("127.0.0.1", description="Address the HTTP server binds to.")
    port: int = Field(
        8000, ge=0, le=65535, description="TCP port of the HTTP server (0 = any free port)."
    )
    data_dir: Path = Field(
        Path("./twinlink-data"),
        description="Folder holding the embedded SQLite store and other state; created if missing.",
    )
    public_url: str = Field(
        "",
        description="Base URL the platform is reached at, used for generated twin ids and links. "
        "Empty means http://{host}:{port}.",
    )
    site_owner: str = Field(
        "",
        description="The dt-id (a URL) of whoever runs this instance, given as `owner` in the "
        "Twinbase-style root index (/index.json). Empty means the public URL.",
    )
    admin_token: SecretStr | None = Field(
        None,
        description="Preset API token for the first admin (for automation). When unset, the first "
        "start generates one and prints it once.",
    )
    admin_password: SecretStr | None = Field(
        None,
        description="Password for the first admin user `admin`. When unset, the first start "
        "generates one and prints it once.",
    )
    session_ttl_s: int = Field(
        12 * 3600, gt=0, description="Lifetime in seconds of the token returned by login."
    )
    max_document_bytes: int = Field(
        1_048_576, gt=0, description="Largest DT document (YAML or JSON) accepted, in bytes."
    )
    public_api_docs: bool = Field(
        False,
        description="Serve /openapi.json without a token. The /docs page itself holds no data "
        "and always asks for a token before it loads the API description.",
    )
    metrics_token: SecretStr | None = Field(
        None,
        description="A token that may read /metrics (and nothing else), for Prometheus's "
        "bearer_token_file. Unset: only admins read /metrics.",
    )
    log_level: Literal["debug", "info", "warning", "error"] = Field(
        "info", description="Log level: debug, info, warning or error."
    )
    log_format: Literal["json", "text"] = Field(
        "json", description="Log line format: json (one object a line) or text."
    )
    access_log: bool = Field(False, description="Log one line per HTTP request.")
    history_sync: Literal["full", "normal"] = Field(
        "full",
        description="How history commits reach the disk: full (fsync every group commit; an "
        "acknowledged sample survives a power cut) or normal (survives a crash of the process, "
        "not of the machine; faster on slow disks).",
    )
    history_retention_days: float = Field(
        0,
        ge=0,
        description="Delete history older than this many days (checked every 10 minutes). "
        "0 keeps everything.",
    )
    history_query_timeout_s: float = Field(
        30,
        gt=0,
        description="Longest a history query (samples, aggregate, downsample, streams, latest) "
        "may run, in seconds; one that takes longer answers 503 saying what to narrow.",
    )
    history_export_timeout_s: float = Field(
        3600,
        gt=0,
        description="Longest a history export may stream, in seconds; one that takes longer "
        "is cut (the connection closes before the end of the body).",
    )
    history_query_max_values: int = Field(
        2_000_000,
        gt=0,
        description="Most values one history answer may hold: a page of samples stops there "
        "(its next_cursor goes on), an aggregate or downsample over it answers 422.",
    )
    max_signals_per_stream: int = Field(
        1000,
        ge=1,
        description="Distinct signals one stream of a twin may have. A batch that would give "
        "its stream more is refused whole (422 over HTTP, an error without retry on the "
        "WebSocket and MQTT); signals already stored keep being accepted.",
    )
    device_token_recheck_s: float = Field(
        60,
        gt=0,
        description="How often the token of an open device WebSocket is checked again, in "
        "seconds; a connection whose token was replaced or revoked (or whose device was "
        "deleted) is closed then.",
    )
    live_queue_messages: int = Field(
        256,
        gt=0,
        description="Messages queued for one live WebSocket client before the oldest are "
        "dropped (and the client told).",
    )
    command_timeout_s: float = Field(
        10,
        gt=0,
        description="Default time a command waits for the device's result before it expires.",
    )
    ready_timeout_s: float = Field(
        1,
        gt=0,
        le=60,
        description="How long /readyz (and /healthz) wait for the store's ping and the bus, in "
        "seconds; a part that has not answered by then makes the node not ready (503), so a "
        "load balancer sends devices to another node.",
    )
    blueprints_dir: Path | None = Field(
        None,
        description="A folder of extra blueprints (`name.py` files or `name/` packages, "
        "Tvilling digital style `class P` included) [<data_dir>/blueprints].",
    )
    max_processors: int = Field(
        64,
        ge=0,
        description="Processors that may run at once on this server (each is a worker process "
        "of about 60 MB); creating or starting one more answers 409.",
    )
    fmu_max_mb: int = Field(512, gt=0, description="Largest FMU file an upload may be, in MB.")
    fmu_env_build_timeout_s: float = Field(
        900,
        gt=0,
        description="Longest pip may take to build a processor's own Python environment "
        "(`python_requirements`, for Python FMUs), in seconds; a build still going then fails "
        "the processor.",
    )
    fmu_uploaders: Literal["admins", "editors"] = Field(
        "admins",
        description="Who may upload and delete FMUs: admins, or also editors of the twin. An "
        "FMU is native code that runs in a worker process under the server's user.",
    )
    max_cosims: int = Field(
        8,
        ge=1,
        description="Co-simulations that may run at once on this server (each in a process of "
        "its own); starting one more answers 409.",
    )
    cosim_max_mb: int = Field(
        1024,
        gt=0,
        description="Largest co-simulation upload, in MB: the file and its unpacked files each.",
    )
    library_max_mb: int = Field(
        1024,
        gt=0,
        description="Largest library push, in MB: the upload and its unpacked files each.",
    )
    library_curators: str = Field(
        "curators",
        min_length=1,
        description="The user group whose members (besides admins) write the library's common "
        "scope.",
    )
    script_runners: Literal["admins", "owners"] = Field(
        "admins",
        description="Who may run a deployment's lifecycle scripts (docs/runs.md): admins, or "
        "also the deployment's owner. A script runs as the server's OS user.",
    )
    runner_tags: str = Field(
        "",
        description="This node's runner tags, comma separated: a run whose package asks for "
        "tags runs only on a node that has all of them.",
    )
    run_default_timeout_s: int = Field(
        3600,
        ge=0,
        description="A lifecycle run's wall-clock limit in seconds when its package gives none; "
        "0: none.",
    )
    run_default_memory_mb: int = Field(
        2048,
        ge=0,
        description="A lifecycle run's address-space limit (RLIMIT_AS) in MB when its package "
        "gives none; 0: none.",
    )
    secret_key: SecretStr | None = Field(
        None,
        description="Key (Fernet, 44 URL-safe base64 characters) that encrypts the gateway's "
        "stored service credentials [made once in <data_dir>/secret.key].",
    )
    gateway_default_twin: str | None = Field(
        None,
        description="The twin whose services answer at /services/{service}/... (the Data Link "
        "paper's form); unset, only /twins/{twin}/services/{service}/... is served.",
    )
    gateway_audit_days: float = Field(
        30, ge=0, description="Keep the gateway's audit log this many days; 0 keeps it all."
    )
    federation_hosts: str = Field(
        "*",
        description="Hosts whose documents may be fetched for relations and imports, comma "
        "separated: `*` any public host, `*.example.org` a domain, `example.org` one host.",
    )
    federation_allow_private: bool = Field(
        False,
        description="Also fetch from loopback, private (RFC 1918, fc00::/7), link-local "
        "(cloud metadata) and CGNAT addresses.",
    )
    federation_max_hops: int = Field(
        5, ge=0, le=20, description="Redirects followed when fetching another instance's document."
    )
    federation_max_kb: int = Field(
        1024, gt=0, description="Largest document fetched from another instance, in KB."
    )
    federation_timeout_s: float = Field(
        5, gt=0, le=120, description="Time limit of one fetch from another instance, in seconds."
    )
    federation_search: bool = Field(
        False, description="Search includes remote twins unless a query says remote=false."
    )
    federation_stale_s: int = Field(
        3600,
        ge=0,
        description="A remote twin's copy older than this many seconds is checked again when "
        "shown.",
    )
    mqtt_mode: Literal["embedded", "external", "off"] = Field(
        "embedded",
        description="MQTT for devices: embedded (the server listens itself), external (it "
        "subscribes to a broker you run) or off.",
    )
    mqtt_host: str = Field("127.0.0.1", description="Address the embedded MQTT listener binds to.")
    mqtt_port: int = Field(
        1883, ge=0, le=65535, description="TCP port of the embedded MQTT listener (0 = any free)."
    )
    mqtt_topic_prefix: str = Field(
        "twinlink",
        pattern=r"^[^#+/\x00][^#+\x00]*[^#+/\x00]$|^[^#+/\x00]$",
        description="First level(s) of every MQTT topic: {prefix}/{twin}/{device}/...",
    )
    mqtt_broker_url: str = Field(
        "mqtt://127.0.0.1:1883",
        pattern=r"^mqtts?://[^/]+$",
        description="External mode: the broker, mqtt://host:port or mqtts://host:port (TLS).",
    )
    mqtt_username: str | None = Field(None, description="External mode: the platform's user name.")
    mqtt_password: SecretStr | None = Field(
        None, description="External mode: the platform's password."
    )
    mqtt_client_id: str = Field(
        "twinlink",
        min_length=1,
        max_length=128,
        description="External mode: the platform's client id (its session at the broker).",
    )
    store_url: SecretStr = Field(
        SecretStr(""),
        description="Where metadata, history, commands and properties are kept: empty for the "
        "embedded SQLite files in the data dir, or a PostgreSQL database, "
        "postgresql://user:password@host:port/database (also postgres://), shared by every "
        "node (docs/scale-out.md). Its password is never shown.",
    )
    bus_url: str = Field(
        "",
        description="The bus between the server's parts: empty for the in-process bus, or Apache "
        "Kafka, kafka://host:port[,host:port...] (the bootstrap brokers), shared by every "
        "node (docs/scale-out.md).",
    )
    bus_publish_timeout_s: float = Field(
        5,
        gt=0,
        le=120,
        description="Kafka only: how long a publish waits for the brokers, in seconds. A device "
        "batch stored but not on the bus by then is answered 503 with Retry-After and sent "
        "again by the device (docs/decisions/0013).",
    )
    workers: int = Field(
        1,
        ge=1,
        le=64,
        description="Server processes on this machine, sharing the HTTP port and the embedded "
        "MQTT listener's (`twinlink up --workers N`). More than 1 needs the shared store and bus "
        "(TWINLINK_STORE_URL and TWINLINK_BUS_URL), as several nodes do (docs/scale-out.md).",
    )
    ui_dir: Path | None = Field(
        None,
        description="Folder of the built web app served at /app/ "
        "[the package's twinlink/web/app, written by `npm run build` in ui/].",
    )
    workspaces_enabled: bool = Field(
        True,
        description="Whether users may start a JupyterLab workspace of their own, run by the "
        "server and reached at /workspaces/{user}/ (docs/workspaces.md).",
    )
    workspace_idle_s: int = Field(
        3600,
        ge=1,
        description="A workspace with no traffic through its proxy for this many seconds is "
        "stopped (its files are kept).",
    )
    workspace_memory_mb: int = Field(
        4096,
        ge=0,
        description="Address-space limit of a workspace's JupyterLab and of each of its kernels, "
        "in MB (0: none).",
    )
    workspace_start_timeout_s: float = Field(
        60,
        gt=0,
        le=600,
        description="How long starting a workspace may take; past it, it is stopped and shown "
        "failed.",
    )
    max_workspaces: int = Field(
        16,
        ge=1,
        description="Workspaces that may run at once on this server (each is a JupyterLab of "
        "about 100 MB plus its kernels); starting one more answers 409.",
    )

    @field_validator("data_dir")
    @classmethod
    def _absolute_data_dir(cls, path: Path) -> Path:
        # Runs and workers work in folders of their own, where a relative path names another.
        return path.expanduser().absolute()

    @field_validator("mqtt_broker_url")
    @classmethod
    def _broker_url(cls, url: str) -> str:
        """A broker URL without credentials and with a valid port. The message never repeats
        the URL: it may hold a password."""
        parts = urlsplit(url)
        if parts.username is not None or parts.password is not None:
            raise ValueError(
                "the URL holds credentials: give them as TWINLINK_MQTT_USERNAME and "
                "TWINLINK_MQTT_PASSWORD instead (a URL ends up in logs and error messages)"
            )
        try:
            parts.port  # noqa: B018 (urlsplit checks the port when it is read)
        except ValueError as err:
            raise ValueError(f"the port is not valid ({err}); use mqtt://host:port") from err
        return url

    @field_validator("store_url")
    @classmethod
    def _store_url(cls, url: SecretStr) -> SecretStr:
        """Empty, or a PostgreSQL URL with a host and a valid port. The message never repeats
        the URL: its password is normal there (kept, never shown)."""
        check_store_url(url.get_secret_value())  # raises ValueError saying what is wrong
        return url

    @field_validator("bus_url")
    @classmethod
    def _bus_url(cls, url: str) -> str:
        if url:
            kafka_bootstrap(url)  # raises ValueError saying what is wrong
        return url

    @model_validator(mode="after")
    def _workers_share(self) -> Settings:
        """Workers are nodes on one machine: they share state and messages only through
        PostgreSQL and Kafka."""
        if self.workers == 1:
            return self
        if not self.store_url.get_secret_value() or not self.bus_url:
            raise ValueError(
                "several workers need the shared store and bus: set TWINLINK_STORE_URL "
                "(PostgreSQL) and TWINLINK_BUS_URL (Kafka), or run one worker"
            )
        return self

    @classmethod
    def settings_customise_sources(
        cls,
        settings_cls: type[BaseSettings],
        init_settings: PydanticBaseSettingsSource,
        env_settings: PydanticBaseSettingsSource,
        dotenv_settings: PydanticBaseSettingsSource,
        file_secret_settings: PydanticBaseSettingsSource,
    ) -> tuple[PydanticBaseSettingsSource, ...]:
        sources: list[PydanticBaseSettingsSource] = [init_settings, env_settings]
        toml_file = os.environ.get("TWINLINK_CONFIG")
        if toml_file:
            if not Path(toml_file).is_file():
                raise ConfigError(f"the settings file {toml_file} does not exist")
            sources.append(TomlConfigSettingsSource(settings_cls, toml_file=Path(toml_file)))
        return tuple(sources)

    @property
    def base_url(self) -> str:
        if self.public_url:
            return self.public_url.rstrip("/")
        host = "127.0.0.1" if self.host in ("0.0.0.0", "::", "") else self.host
        return f"http://{host}:{self.port}"

    @property
    def store_shown(self) -> str:
        """The store for logs and messages: `sqlite` or the URL without its password."""
        return shown_store_url(self.store_url.get_secret_value())


def load_settings(config_file: str | None = None, **overrides: Any) -> Settings:
    """Build settings; `overrides` (CLI flags) win over the environment and the file."""
    if config_file:
        os.environ["TWINLINK_CONFIG"] = config_file
    clean = {k: v for k, v in overrides.items() if v is not None}
    try:
        return Settings(**clean)
    except ValidationError as err:
        lines = [
            # A check of several settings together (loc empty) names them in its message.
            (f"TWINLINK_{'_'.join(str(x) for x in e['loc']).upper()}: " if e["loc"] else "")
            + e["msg"].removeprefix("Value error, ")  # what a validator of ours says
            for e in err.errors(include_url=False)
        ]
        # from None: pydantic's error repeats the values, the secret key's among them.
        raise ConfigError("invalid settings:\n  " + "\n  ".join(lines)) from None
    except tomllib.TOMLDecodeError as err:
        raise ConfigError(f"the settings file is not valid TOML: {err}") from err
