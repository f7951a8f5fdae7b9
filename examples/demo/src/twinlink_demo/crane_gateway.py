"""How the API gateway signs in to each crane service, keyed by the gateway service name of
the DT document feature the service fills (`Sensor manager` -> `sensor-manager`)."""

from __future__ import annotations

from typing import Any

from ilmatar_crane import Crane
from twinlink.gateway.spec import service_name

# DT document feature (examples/ilmatar/ilmatar-public.yaml) -> the crane service behind it.
FEATURES = {
    "Historian": "historian",
    "OPC UA server": "bridge",
    "CAD store": "cad",
    "Sensor manager": "sensors",
}

# A `health_path` for each gateway service, relative to its base URL. Each needs the service's
# credentials, so a healthy answer also shows that the gateway can sign in.
HEALTH_PATHS = {
    "historian": "signals",
    "opc-ua-server": "variables",
    "cad-store": "files",
    "sensor-manager": "sensors",
}


def gateway_auth(crane: Crane) -> dict[str, dict[str, Any]]:
    """Each feature's gateway auth settings, in the gateway's `auth` shape."""
    creds = crane.credentials
    auth: dict[str, dict[str, Any]] = {
        "Historian": {
            "method": "custom_login",
            "login_url": crane.root_url("historian") + "api/login",
            "body": {"username": creds.historian_username, "password": creds.historian_password},
            "token_path": "data.token",
            "expires_in_path": "data.expires_in",
            "header": "Authorization",
            "template": "Token {token}",
        },
        "OPC UA server": {
            "method": "api_key",
            "name": "X-API-Key",
            "value": creds.bridge_api_key,
            "in": "header",
        },
        "CAD store": {"method": "bearer", "token": creds.cad_token},
        "Sensor manager": {
            "method": "oauth2_client_credentials",
            "token_url": crane.root_url("sensors") + "oauth/token",
            "client_id": creds.sensors_client_id,
            "client_secret": creds.sensors_client_secret,
            "scope": None,
        },
    }
    return {service_name(feature): settings for feature, settings in auth.items()}


def gateway_password_auth(crane: Crane) -> dict[str, Any]:
    """The sensor manager's other grant, OAuth 2.0 password, for trying it instead."""
    creds = crane.credentials
    return {
        "method": "oauth2_password",
        "token_url": crane.root_url("sensors") + "oauth/token",
        "username": creds.sensors_username,
        "password": creds.sensors_password,
        "client_id": creds.sensors_client_id,
        "client_secret": creds.sensors_client_secret,
    }


def gateway_base_urls(crane: Crane) -> dict[str, str]:
    """Each feature's API base URL; with the default ports these are the `apiAddress` values
    of the Ilmatar DT document."""
    return {service_name(f): crane.urls[service] for f, service in FEATURES.items()}
