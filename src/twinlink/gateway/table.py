"""The services of each twin, as the gateway uses them: built from the DT document's features
(those with an `apiAddress`) and the services added by API, with their stored settings and
decrypted credentials, cached until a document or a service changes."""

from __future__ import annotations

import bisect
import logging
from dataclasses import dataclass, field
from typing import Any
from urllib.parse import urlsplit

from twinlink.auth.vault import Vault, VaultError
from twinlink.domain.merge import merge_parts
from twinlink.domain.records import ServiceRecord, TwinRecord
from twinlink.gateway.credentials.base import Credentials
from twinlink.gateway.credentials.methods import credentials_for, shown_auth
from twinlink.gateway.credentials.shared import TokenShare
from twinlink.gateway.credentials.static import NoConfig, NoCredentials
from twinlink.gateway.credentials.token import TokenCredentials
from twinlink.gateway.spec import (
    READ_METHODS,
    ServiceSettings,
    check_base_url,
    origin,
    service_name,
)
from twinlink.gateway.upstream import Origin
from twinlink.plugins import split_secrets
from twinlink.store.base import MetadataStore
from twinlink.store.tokens import SharedTokens

log = logging.getLogger("twinlink.gateway")


# Upper bounds (s) of the histogram of the services' answer times, as Prometheus buckets.
BUCKETS = (0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10)


@dataclass(slots=True)
class ServiceStats:
    requests: dict[int, int] = field(default_factory=dict)  # status -> count
    failures: dict[str, int] = field(default_factory=dict)  # outcome -> count
    bytes_in: int = 0
    bytes_out: int = 0
    upstream_counts: list[int] = field(default_factory=lambda: [0] * (len(BUCKETS) + 1))
    upstream_sum_s: float = 0.0
    health: dict[str, Any] | None = None

    def observe(self, seconds: float) -> None:
        self.upstream_sum_s += seconds
        self.upstream_counts[bisect.bisect_left(BUCKETS, seconds)] += 1

    def summary(self) -> dict[str, Any]:
        """The figures the web app's gateway monitor shows: answers by status, failures by
        outcome, bytes, and the service's answer time (mean, and p50/p95 as the upper bound
        of their histogram bucket; None above the last bucket)."""
        count = sum(self.upstream_counts)
        upstream: dict[str, float | None] | None = None
        if count:
            upstream = {
                "mean": round(self.upstream_sum_s / count * 1000, 3),
                "p50": self._quantile_ms(0.5, count),
                "p95": self._quantile_ms(0.95, count),
            }
        return {
            "statuses": {str(k): v for k, v in sorted(self.requests.items())},
            "failures": dict(self.failures),
            "bytes_in": self.bytes_in,
            "bytes_out": self.bytes_out,
            "upstream_ms": upstream,
        }

    def _quantile_ms(self, q: float, count: int) -> float | None:
        seen = 0
        for i, n in enumerate(self.upstream_counts):
            seen += n
            if seen >= q * count:
                return BUCKETS[i] * 1000 if i < len(BUCKETS) else None
        return None


@dataclass(slots=True)
class Service:
    """One service ready to forward to. Shared by concurrent requests: read only, except
    `credentials` (which renews itself) and `stats`."""

    twin_id: int
    twin_slug: str
    name: str
    source: str  # document | api
    base_url: str | None  # None: a stored document service whose feature is gone
    settings: ServiceSettings
    credentials: Credentials[Any]
    feature: dict[str, Any] | None
    record: ServiceRecord | None
    blocked: str | None = None  # why requests cannot be forwarded now
    origin: Origin | None = None
    host_header: bytes = b""
    base_path: str = "/"
    methods: frozenset[str] = READ_METHODS
    stats: ServiceStats = field(default_factory=ServiceStats)

    def __post_init__(self) -> None:
        self.methods = frozenset(self.settings.methods)
        if self.base_url is None:
            self.blocked = self.blocked or "the DT document no longer lists this feature"
            return
        parts = urlsplit(self.base_url)
        scheme = parts.scheme
        port = parts.port or (443 if scheme == "https" else 80)
        tls = self.settings.tls.context() if scheme == "https" else None
        self.origin = Origin(scheme, parts.hostname or "", port, tls)
        self.host_header = parts.netloc.encode("idna")
        self.base_path = parts.path or "/"

    def public(self) -> dict[str, Any]:
        s = self.settings
        public_auth, _ = split_secrets(s.auth)
        return {
            "name": self.name,
            "twin": self.twin_slug,
            "source": self.source,
            "base_url": self.base_url,
            "feature": None if self.feature is None else self.feature.get("name"),
            "description": s.description or (self.feature or {}).get("description"),
            "auth": shown_auth(public_auth, _set_secrets(self.record)),
            "methods": s.methods,
            "limits": s.limits.model_dump(),
            "health_path": s.health_path,
            "websocket": s.websocket,
            "tls": {"verify": s.tls.verify, "ca_pem_set": s.tls.ca_pem is not None},
            "blocked": self.blocked,
            "gateway_path": f"/twins/{self.twin_slug}/services/{self.name}/",
        }


def _set_secrets(record: ServiceRecord | None) -> set[str]:
    if record is None:
        return set()
    return set(record.settings.get("secret_keys", []))


def document_features(parts: dict[str, dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Service name -> feature, for each feature of the merged document with an apiAddress."""
    merged = merge_parts(parts)
    found: dict[str, dict[str, Any]] = {}
    for feature in merged.get("features") or []:
        if isinstance(feature, dict) and feature.get("apiAddress") and feature.get("name"):
            name = service_name(str(feature["name"]))
            if name:
                found.setdefault(name, feature)
    return found


class ServiceBuilder:
    """Turns stored records and document features into `Service`s, keeping each service's
    credentials object (and so its cached token) while its settings are unchanged."""

    def __init__(
        self, store: MetadataStore, vault: Vault, tokens: SharedTokens | None = None
    ) -> None:
        self.store = store
        self.vault = vault
        self.tokens = tokens  # the nodes' shared tokens; None on the embedded store
        self._credentials: dict[tuple[int, str, int], Credentials[Any]] = {}
        self.stats: dict[tuple[int, str], ServiceStats] = {}
        self.slugs: dict[int, str] = {}  # twin id -> slug, for the metrics' labels

    def credentials_by_service(self) -> dict[tuple[int, str], Credentials[Any]]:
        return {(k[0], k[1]): v for k, v in self._credentials.items()}

    async def build(self, twin: TwinRecord) -> dict[str, Service]:
        self.slugs[twin.id] = twin.slug
        features = document_features(await self.store.get_parts(twin.id))
        records = {r.name: r for r in await self.store.list_services(twin.id)}
        services: dict[str, Service] = {}
        for name in sorted(set(features) | set(records)):
            feature, record = features.get(name), records.get(name)
            if record is not None and record.source == "api" and feature is not None:
                feature = None  # an API service of the same name wins; the list says so
            services[name] = self._service(twin, name, feature, record)
        return services

    def _service(
        self,
        twin: TwinRecord,
        name: str,
        feature: dict[str, Any] | None,
        record: ServiceRecord | None,
    ) -> Service:
        stored = dict(record.settings) if record is not None else {}
        stored.pop("secret_keys", None)
        blocked = None
        secret: dict[str, Any] = {}
        if record is not None and record.secret is not None:
            try:
                secret = self.vault.unseal(record.secret)
            except VaultError as err:
                blocked = str(err)
        auth = {**stored.get("auth", {"method": "none"}), **secret}
        base_url = stored.get("base_url")
        source = "api" if record is not None and record.source == "api" else "document"
        if source == "document":
            base_url = None
            if feature is not None:
                try:
                    base_url = check_base_url(str(feature["apiAddress"]))
                except ValueError as err:
                    blocked = f"the feature's apiAddress is not usable: {err}"
        try:
            settings = ServiceSettings.model_validate({**stored, "auth": auth, "base_url": None})
        except ValueError as err:
            settings, blocked = ServiceSettings(), f"the stored settings are not valid: {err}"
        if (
            blocked is None
            and base_url is not None
            and record is not None
            and settings.auth.method != "none"
            and record.auth_origin != origin(base_url)
        ):
            # No origin: the credentials were set while the feature was gone from the document.
            blocked = (
                "the service's address changed since its credentials were set (they were "
                f"set for {record.auth_origin or 'no address'}); an owner must set them again"
            )
        key = (twin.id, name, record.modified_ns if record is not None else 0)
        credentials, failed = self._credentials_for(key, settings)
        return Service(
            twin_id=twin.id,
            twin_slug=twin.slug,
            name=name,
            source=source,
            base_url=base_url,
            settings=settings,
            credentials=credentials,
            feature=feature,
            record=record,
            blocked=blocked or failed,
            stats=self.stats.setdefault((twin.id, name), ServiceStats()),
        )

    def _credentials_for(
        self, key: tuple[int, str, int], settings: ServiceSettings
    ) -> tuple[Credentials[Any], str | None]:
        """The service's credentials object, kept while its settings are unchanged; and why
        the service is blocked if its method cannot make one (a plug-in's bug)."""
        credentials = self._credentials.get(key)
        if credentials is not None:
            return credentials, None
        try:
            credentials = credentials_for(settings.auth)
        except Exception as err:
            log.exception("the %s credential method failed", settings.auth.method)
            reason = f"its {settings.auth.method} credentials failed ({type(err).__name__})"
            return NoCredentials(NoConfig()), reason
        if self.tokens is not None and isinstance(credentials, TokenCredentials):
            # One login among the nodes, not one per node (credentials/shared.py).
            service = f"twin {key[0]} service {key[1]}"
            credentials.share = TokenShare(self.tokens, self.vault, service, settings.auth)
        self._credentials[key] = credentials
        return credentials, None

    def forget(self, twin_id: int, name: str) -> None:
        for key in [k for k in self._credentials if k[0] == twin_id and k[1] == name]:
            del self._credentials[key]
        self.stats.pop((twin_id, name), None)
