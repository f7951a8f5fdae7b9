"""The backends' URLs: PostgreSQL's checked and shown without its password, Kafka's brokers
read from a `kafka://` URL. Pure rules (no I/O), used by the settings and the backends."""

from __future__ import annotations

from urllib.parse import urlsplit

POSTGRES_SCHEMES = ("postgresql", "postgres")


def shown_store_url(url: str) -> str:
    """A store URL fit to log: its password replaced by `***` ("sqlite" when empty)."""
    if not url:
        return "sqlite"
    parts = urlsplit(url)
    if parts.password is None:
        return url
    netloc = parts.netloc.rsplit("@", 1)[1]
    user = parts.username or ""
    return parts._replace(netloc=f"{user}:***@{netloc}").geturl()


def kafka_bootstrap(url: str) -> str:
    """ "host:port,host:port" of a `kafka://host:port[,host:port...]` URL; ValueError saying
    what is wrong with it. (urlsplit cannot read the port of a list of brokers.)"""
    form = "kafka://host:port[,host:port...]"
    scheme, sep, rest = url.partition("://")
    if not sep or scheme != "kafka":
        raise ValueError(f"only Apache Kafka is supported: give {form}, or leave it empty")
    if "@" in rest or "?" in rest or "/" in rest.rstrip("/"):
        raise ValueError(
            f"give the brokers alone, {form}: no credentials, path or options (the bus "
            "connects in plain text; docs/scale-out.md)"
        )
    brokers = []
    for broker in rest.rstrip("/").split(","):
        host, colon, port = broker.strip().rpartition(":")
        if not colon or not host or not port.isdigit() or not 0 < int(port) < 65536:
            raise ValueError(f"{broker.strip() or 'an empty entry'} is not host:port; use {form}")
        brokers.append(f"{host}:{int(port)}")
    return ",".join(brokers)


def check_store_url(value: str) -> None:
    """Empty, or a PostgreSQL URL with a host and a valid port; else ValueError saying what is
    wrong. The message never repeats the URL: its password is normal there."""
    if not value:
        return
    parts = urlsplit(value)
    if parts.scheme not in POSTGRES_SCHEMES:
        raise ValueError(
            "only PostgreSQL is supported: give postgresql://user:password@host:port/"
            "database, or leave it empty for the embedded SQLite store"
        )
    if not parts.hostname:
        raise ValueError("the URL names no host: postgresql://user:password@host:port/database")
    try:
        parts.port  # noqa: B018 (urlsplit checks the port when it is read)
    except ValueError:
        raise ValueError(
            "the port is not valid: postgresql://user:password@host:port/database"
        ) from None  # the error's text repeats the URL's netloc, password included
