from __future__ import annotations

from pathlib import Path

import pytest

from twinlink.config import ConfigError, Settings, load_settings

DOCS = Path(__file__).resolve().parents[2] / "docs" / "config.md"


def test_defaults() -> None:
    s = Settings()
    assert (s.host, s.port, s.base_url) == ("127.0.0.1", 8000, "http://127.0.0.1:8000")


def test_the_data_dir_is_made_absolute_from_where_the_server_starts(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Lifecycle runs and co-simulation workers work in folders of their own: a relative data
    dir (the default ./twinlink-data, the demo's .twinlink-demo) would name another folder
    there (a deployment's execute phase could not find its own script)."""
    monkeypatch.chdir(tmp_path)
    assert Settings().data_dir == tmp_path / "twinlink-data"
    assert load_settings(None, data_dir=Path("here/data")).data_dir == tmp_path / "here" / "data"
    assert Settings(data_dir=Path("/srv/twinlink")).data_dir == Path("/srv/twinlink")


def test_env_then_toml_then_flags(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    toml = tmp_path / "twinlink.toml"
    toml.write_text('port = 9001\nhost = "0.0.0.0"\npublic_url = "https://twins.example.org/"\n')
    monkeypatch.setenv("TWINLINK_CONFIG", str(toml))
    monkeypatch.setenv("TWINLINK_PORT", "9002")
    s = Settings()
    assert (s.host, s.port) == ("0.0.0.0", 9002)  # env beats the file
    assert s.base_url == "https://twins.example.org"
    assert load_settings(None, port=9003).port == 9003  # flags beat env


def test_unknown_setting_is_an_error(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    toml = tmp_path / "t.toml"
    toml.write_text("prot = 1\n")
    monkeypatch.setenv("TWINLINK_CONFIG", str(toml))
    with pytest.raises(ValueError, match="prot"):
        Settings()


@pytest.mark.parametrize(
    ("url", "says"),
    [
        ("mqtt://platform:s3cret@broker.example.org:1883", "TWINLINK_MQTT_PASSWORD instead"),
        ("mqtts://:s3cret@broker.example.org", "TWINLINK_MQTT_PASSWORD instead"),
        ("mqtt://platform:s3cret@broker.example.org:99999", "TWINLINK_MQTT_PASSWORD instead"),
        ("mqtt://broker.example.org:99999", "the port is not valid"),
    ],
)
def test_a_broker_url_with_credentials_or_a_bad_port_is_refused_without_repeating_it(
    url: str, says: str
) -> None:
    with pytest.raises(ConfigError) as refused:
        load_settings(None, mqtt_broker_url=url)
    message = str(refused.value)
    assert "TWINLINK_MQTT_BROKER_URL: " in message and says in message
    assert "Value error" not in message
    assert "s3cret" not in message and url not in message


def test_a_broker_url_without_credentials_is_taken() -> None:
    assert load_settings(None, mqtt_broker_url="mqtts://broker.example.org").mqtt_broker_url == (
        "mqtts://broker.example.org"
    )


def test_secrets_do_not_show_in_repr(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("TWINLINK_ADMIN_TOKEN", "tl_very_secret")
    assert "tl_very_secret" not in repr(Settings())


@pytest.mark.parametrize("field", sorted(Settings.model_fields))
def test_every_setting_is_documented(field: str) -> None:
    text = DOCS.read_text()
    assert f"`TWINLINK_{field.upper()}`" in text, (
        f"document TWINLINK_{field.upper()} in docs/config.md"
    )
