"""TWINLINK_STORE_URL and TWINLINK_BUS_URL: checked at start, the store's password never shown
(issue 15; docs/config.md, docs/scale-out.md)."""

from __future__ import annotations

import logging

import pytest
from click.testing import CliRunner

from twinlink.cli import main
from twinlink.config import ConfigError, Settings, load_settings

PASSWORD = "s3cret-Pa55"


def test_both_are_empty_by_default_the_embedded_store_and_the_in_process_bus() -> None:
    s = Settings()
    assert s.store_url.get_secret_value() == "" and s.bus_url == ""
    assert s.store_shown == "sqlite"


@pytest.mark.parametrize("scheme", ["postgresql", "postgres"])
def test_a_postgresql_url_is_kept_whole_and_shown_without_its_password(scheme: str) -> None:
    url = f"{scheme}://twin:{PASSWORD}@db.example.org:5433/twinlink"
    s = load_settings(None, store_url=url)
    assert s.store_url.get_secret_value() == url  # what asyncpg gets, password included
    assert s.store_shown == f"{scheme}://twin:***@db.example.org:5433/twinlink"
    assert PASSWORD not in repr(s) and PASSWORD not in str(s)


def test_a_postgresql_url_without_a_password_is_shown_as_it_is() -> None:
    s = load_settings(None, store_url="postgresql://twin@db/twinlink")
    assert s.store_shown == "postgresql://twin@db/twinlink"


@pytest.mark.parametrize(
    ("url", "says"),
    [
        (f"mysql://twin:{PASSWORD}@db/twinlink", "only PostgreSQL is supported"),
        (f"sqlite:///{PASSWORD}", "only PostgreSQL is supported"),
        (f"postgresql://twin:{PASSWORD}@db:99999/twinlink", "the port is not valid"),
        (f"postgresql://twin:{PASSWORD}@db:port/twinlink", "the port is not valid"),
        (f"postgresql://twin:{PASSWORD}@/twinlink", "names no host"),
    ],
)
def test_a_bad_store_url_is_refused_without_repeating_it(url: str, says: str) -> None:
    with pytest.raises(ConfigError) as err:
        load_settings(None, store_url=url)
    assert "TWINLINK_STORE_URL" in str(err.value) and says in str(err.value)
    assert PASSWORD not in str(err.value)


@pytest.mark.parametrize(
    ("url", "servers"),
    [
        ("kafka://127.0.0.1:9092", "127.0.0.1:9092"),
        ("kafka://k1:9092,k2:9093, k3:9094/", "k1:9092,k2:9093,k3:9094"),
        ("kafka://[::1]:9092", "[::1]:9092"),
    ],
)
def test_a_kafka_url_names_its_brokers(url: str, servers: str) -> None:
    from twinlink.domain.backend_urls import kafka_bootstrap

    assert load_settings(None, bus_url=url).bus_url == url
    assert kafka_bootstrap(url) == servers


@pytest.mark.parametrize(
    ("url", "says"),
    [
        ("amqp://broker:5672", "only Apache Kafka is supported"),
        ("broker:9092", "only Apache Kafka is supported"),
        (f"kafka://user:{PASSWORD}@broker:9092", "no credentials"),
        ("kafka://broker:9092/topic", "no credentials, path or options"),
        ("kafka://broker", "broker is not host:port"),
        ("kafka://broker:9092,,other:9092", "an empty entry is not host:port"),
        ("kafka://broker:0", "broker:0 is not host:port"),
    ],
)
def test_a_bad_bus_url_is_refused_saying_what_to_give(url: str, says: str) -> None:
    with pytest.raises(ConfigError) as err:
        load_settings(None, bus_url=url)
    assert "TWINLINK_BUS_URL" in str(err.value) and says in str(err.value)
    assert PASSWORD not in str(err.value)


def test_up_takes_them_as_flags_and_stops_on_a_bad_one_with_the_message(
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.DEBUG)
    store = f"mysql://twin:{PASSWORD}@db/twinlink"
    done = CliRunner().invoke(main, ["up", "--store-url", store, "--bus-url", "kafka://k:1"])
    assert done.exit_code != 0
    assert "TWINLINK_STORE_URL: only PostgreSQL is supported" in done.output
    assert PASSWORD not in done.output and PASSWORD not in caplog.text
    done = CliRunner().invoke(main, ["up", "--bus-url", "kafka://k"])
    assert done.exit_code != 0 and "TWINLINK_BUS_URL: k is not host:port" in done.output


PG = f"postgresql://twin:{PASSWORD}@db/twinlink"


def test_one_worker_by_default_and_several_with_the_shared_store_and_bus() -> None:
    assert Settings().workers == 1
    s = load_settings(None, workers=3, store_url=PG, bus_url="kafka://k1:9092")
    assert s.workers == 3


@pytest.mark.parametrize(
    ("overrides", "says"),
    [
        ({}, "several workers need the shared store and bus"),
        ({"store_url": PG}, "several workers need the shared store and bus"),
        ({"bus_url": "kafka://k1:9092"}, "several workers need the shared store and bus"),
    ],
)
def test_several_workers_without_what_they_share_are_refused(
    overrides: dict[str, str], says: str
) -> None:
    with pytest.raises(ConfigError) as refused:
        load_settings(None, workers=2, **overrides)
    assert says in str(refused.value)
    assert "TWINLINK_:" not in str(refused.value)  # a check of several settings names them
    assert PASSWORD not in str(refused.value)


def test_up_with_workers_but_no_postgres_says_what_to_set() -> None:
    done = CliRunner().invoke(main, ["up", "--workers", "2", "--port", "0"])
    assert done.exit_code != 0
    assert "TWINLINK_STORE_URL" in done.output and "TWINLINK_BUS_URL" in done.output
