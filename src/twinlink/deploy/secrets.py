"""What a deployment keeps secret: its devices' tokens, and the parameters its package's schema
marks as secret (`writeOnly: true` or `format: password`). Both are sealed with the server's
vault (auth/vault.py) in the deployment's record; the record's `parameters` show a secret one
as `***`, and plans and the journal show its value nowhere."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from twinlink.auth.vault import Vault
from twinlink.deploy.plan import MASK
from twinlink.domain.deployments import DeploymentRecord


def secret_names(schema: dict[str, Any] | None) -> frozenset[str]:
    """The parameters the schema marks as secret."""
    properties = (schema or {}).get("properties")
    if not isinstance(properties, dict):
        return frozenset()
    return frozenset(
        name
        for name, sub in properties.items()
        if isinstance(sub, dict)
        and (sub.get("writeOnly") is True or sub.get("format") == "password")
    )


@dataclass(slots=True)
class Sealed:
    device_tokens: dict[str, str] = field(default_factory=dict)
    parameters: dict[str, Any] = field(default_factory=dict)  # the secret ones


def unseal(vault: Vault, record: DeploymentRecord) -> Sealed:
    if record.secrets is None:
        return Sealed()
    data = vault.unseal(record.secrets)
    return Sealed(dict(data.get("device_tokens", {})), dict(data.get("parameters", {})))


def seal(vault: Vault, sealed: Sealed) -> bytes | None:
    if not sealed.device_tokens and not sealed.parameters:
        return None
    return vault.seal({"device_tokens": sealed.device_tokens, "parameters": sealed.parameters})


def split(params: dict[str, Any], names: frozenset[str]) -> tuple[dict[str, Any], dict[str, Any]]:
    """(the parameters as the record shows them, secret ones as ***; the secret ones)."""
    secret = {k: v for k, v in params.items() if k in names}
    return {k: MASK if k in names else v for k, v in params.items()}, secret


def hidden_values(params: dict[str, Any], names: frozenset[str]) -> frozenset[str]:
    """The secret parameters' values as text, to be masked wherever they were written in."""
    return frozenset(str(v) for k, v in params.items() if k in names and v not in (None, ""))


def parameters_of(vault: Vault, record: DeploymentRecord) -> dict[str, Any]:
    """The deployment's parameters with the secret ones' values."""
    return {**record.parameters, **unseal(vault, record).parameters}


def with_tokens(vault: Vault, record: DeploymentRecord, tokens: dict[str, str]) -> bytes | None:
    """The record's secrets with device `tokens` added."""
    sealed = unseal(vault, record)
    sealed.device_tokens.update(tokens)
    return seal(vault, sealed)


def set_parameters(
    vault: Vault, record: DeploymentRecord, params: dict[str, Any], names: frozenset[str]
) -> None:
    """Give the record `params`: the secret ones (`names`) sealed, shown as ***."""
    sealed = unseal(vault, record)
    record.parameters, sealed.parameters = split(params, names)
    record.secrets = seal(vault, sealed)
