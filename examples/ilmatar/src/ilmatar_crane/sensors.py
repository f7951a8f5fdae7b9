"""The sensor manager: an OSEMA-like REST API for the sensors retrofitted to the crane (two laser
distance sensors and a 3-axis accelerometer on the hook), behind OAuth 2.0.

`POST /oauth/token` (form-encoded, RFC 6749) issues Bearer tokens for two grants:
`client_credentials`, and `password` with the operator's username and password. Both need the
client's id and secret, in HTTP Basic auth or in the form (RFC 6749 section 2.3.1).
"""

from __future__ import annotations

import base64
import binascii
import math
import secrets
import time
from collections.abc import Awaitable, Callable, Mapping
from dataclasses import asdict, dataclass
from typing import Any
from urllib.parse import parse_qs, unquote_plus

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Route

from ilmatar_crane._http import health, json_body, json_error, page_routes
from ilmatar_crane._tokens import IssuesTokens, TokenStore
from ilmatar_crane.historian import iso
from ilmatar_crane.plant import CranePlant

REALM = "sensor-manager"
ENDPOINTS = (
    ("POST /oauth/token", "OAuth 2.0 token: grant_type=client_credentials or password."),
    ("GET /api/sensors", "The crane's retrofitted sensors."),
    ("GET /api/sensors/{id}", "One sensor."),
    ("PATCH /api/sensors/{id}", 'Change name, status or sample rate: {"sample_rate_hz": 20}.'),
    ("GET /api/sensors/{id}/latest", "The sensor's current reading."),
    ("GET /health", "Liveness (no token needed)."),
)
STATUSES = ("active", "inactive")
Handler = Callable[[Request], Awaitable[Response]]


@dataclass
class Sensor:
    id: str
    name: str
    type: str
    unit: str
    sample_rate_hz: float
    max_sample_rate_hz: float
    status: str
    mounting: str


def _laser(sensor_id: str, name: str, mounting: str) -> Sensor:
    return Sensor(sensor_id, name, "laser_distance", "m", 10.0, 50.0, "active", mounting)


def crane_sensors() -> dict[str, Sensor]:
    sensors = (
        _laser(
            "bridge-laser",
            "Bridge position laser",
            "End carriage, aimed along the runway at the hall's end wall.",
        ),
        _laser(
            "trolley-laser",
            "Trolley position laser",
            "Trolley frame, aimed along the girder at the end carriage.",
        ),
        Sensor(
            id="hook-accelerometer",
            name="Hook accelerometer",
            type="accelerometer_3axis",
            unit="m/s^2",
            sample_rate_hz=100.0,
            max_sample_rate_hz=1000.0,
            status="active",
            mounting="Hook block crosshead; x along the runway, y along the girder, z up.",
        ),
    )
    return {s.id: s for s in sensors}


def oauth_error(status: int, error: str, description: str) -> JSONResponse:
    # RFC 6749 section 5.2: the token endpoint's own error shape.
    headers = {"Cache-Control": "no-store"}
    if error == "invalid_client":
        headers["WWW-Authenticate"] = f'Basic realm="{REALM}"'
    body = {"error": error, "error_description": description}
    return JSONResponse(body, status_code=status, headers=headers)


def basic_credentials(header: str) -> tuple[str, str] | None:
    scheme, _, encoded = header.partition(" ")
    if scheme.lower() != "basic":
        return None
    try:
        decoded = base64.b64decode(encoded.strip(), validate=True).decode("utf-8")
    except (binascii.Error, UnicodeDecodeError):
        return None
    client_id, sep, secret = decoded.partition(":")
    # RFC 6749 section 2.3.1: both parts are form-encoded before Basic encoding.
    return (unquote_plus(client_id), unquote_plus(secret)) if sep else None


class SensorManager(IssuesTokens):
    def __init__(
        self,
        plant: CranePlant,
        *,
        clients: Mapping[str, str],
        users: Mapping[str, str],
        token_ttl_s: float = 300.0,
    ) -> None:
        self._plant = plant
        self._clients = dict(clients)
        self._users = dict(users)
        self._tokens = TokenStore(token_ttl_s)
        self.sensors = crane_sensors()
        routes = [
            Route("/health", health),
            Route("/oauth/token", self._token, methods=["POST"]),
            Route("/api/sensors", self._guard(self._list)),
            Route("/api/sensors/{id}", self._guard(self._get)),
            Route("/api/sensors/{id}", self._guard(self._patch), methods=["PATCH"]),
            Route("/api/sensors/{id}/latest", self._guard(self._latest)),
            *page_routes("Ilmatar sensor manager", "Retrofitted sensors of the crane.", ENDPOINTS),
        ]
        self.app = Starlette(routes=routes)

    async def _token(self, request: Request) -> Response:
        if request.headers.get("content-type", "").split(";")[0].strip() != (
            "application/x-www-form-urlencoded"
        ):
            return oauth_error(400, "invalid_request", "Send a form-encoded body.")
        raw = parse_qs((await request.body()).decode("utf-8", "replace"), keep_blank_values=True)
        if any(len(values) > 1 for values in raw.values()):
            return oauth_error(400, "invalid_request", "A parameter was repeated.")
        form = {key: values[0] for key, values in raw.items()}
        client = self._authenticate_client(request, form)
        if isinstance(client, Response):
            return client
        grant = form.get("grant_type")
        if grant == "client_credentials":
            subject = client
        elif grant == "password":
            username, password = form.get("username", ""), form.get("password", "")
            if not self._check(self._users, username, password):
                return oauth_error(400, "invalid_grant", "Unknown user or wrong password.")
            subject = username
        elif grant is None:
            return oauth_error(400, "invalid_request", "grant_type is missing.")
        else:
            return oauth_error(400, "unsupported_grant_type", "Use client_credentials or password.")
        ttl = self._tokens.ttl_s
        body = {
            "access_token": self._tokens.issue(subject),
            "token_type": "Bearer",
            "expires_in": int(ttl) if float(ttl).is_integer() else ttl,
        }
        return JSONResponse(body, headers={"Cache-Control": "no-store", "Pragma": "no-cache"})

    def _authenticate_client(self, request: Request, form: dict[str, str]) -> str | Response:
        header = request.headers.get("Authorization")
        in_body = "client_id" in form or "client_secret" in form
        if header and in_body:
            return oauth_error(400, "invalid_request", "Authenticate the client one way only.")
        if header:
            found = basic_credentials(header)
        else:
            found = (form.get("client_id", ""), form.get("client_secret", ""))
        if found is None or not self._check(self._clients, *found):
            return oauth_error(401, "invalid_client", "Unknown client or wrong client secret.")
        return found[0]

    @staticmethod
    def _check(known: Mapping[str, str], name: str, secret: str) -> bool:
        expected = known.get(name)
        return expected is not None and secrets.compare_digest(secret.encode(), expected.encode())

    def _guard(self, handler: Handler) -> Handler:
        async def guarded(request: Request) -> Response:
            scheme, _, token = request.headers.get("Authorization", "").partition(" ")
            if scheme.lower() != "bearer" or not token.strip():
                challenge = f'Bearer realm="{REALM}"'
                detail = "Get a token at POST /oauth/token and send it as a Bearer token."
            elif self._tokens.subject(token.strip()) is None:
                challenge = (
                    f'Bearer realm="{REALM}", error="invalid_token", '
                    'error_description="The access token is unknown or has expired"'
                )
                detail = "The access token is unknown or has expired; get a new one."
            else:
                return await handler(request)
            return json_error(401, "unauthorized", detail, {"WWW-Authenticate": challenge})

        return guarded

    def _sensor(self, request: Request) -> Sensor | Response:
        sensor = self.sensors.get(request.path_params["id"])
        if sensor is None:
            known = ", ".join(self.sensors)
            return json_error(404, "not_found", f"No such sensor; the sensors are {known}.")
        return sensor

    async def _list(self, request: Request) -> Response:
        return JSONResponse({"sensors": [asdict(s) for s in self.sensors.values()]})

    async def _get(self, request: Request) -> Response:
        sensor = self._sensor(request)
        return sensor if isinstance(sensor, Response) else JSONResponse(asdict(sensor))

    async def _patch(self, request: Request) -> Response:
        sensor = self._sensor(request)
        if isinstance(sensor, Response):
            return sensor
        body = await json_body(request)
        if isinstance(body, Response):
            return body
        problem = _patch_problem(sensor, body)
        if problem is not None:
            return json_error(422, "invalid_value", problem)
        for key, value in body.items():
            setattr(sensor, key, float(value) if key == "sample_rate_hz" else value)
        return JSONResponse(asdict(sensor))

    async def _latest(self, request: Request) -> Response:
        sensor = self._sensor(request)
        if isinstance(sensor, Response):
            return sensor
        if sensor.status != "active":
            return json_error(409, "sensor_inactive", f"{sensor.id} is inactive; PATCH it on.")
        reading: dict[str, Any] = {"sensor": sensor.id, "time": iso(time.time())}
        reading["unit"] = sensor.unit
        if sensor.id == "hook-accelerometer":
            x, y, z = self._plant.hook_acceleration
            reading["value"] = {"x": round(x, 4), "y": round(y, 4), "z": round(z, 4)}
        else:
            axis = self._plant.bridge if sensor.id == "bridge-laser" else self._plant.trolley
            reading["value"] = round(axis.position, 4)
        return JSONResponse(reading)


def _patch_problem(sensor: Sensor, body: dict[str, Any]) -> str | None:
    """Why the PATCH body cannot be applied, or None; nothing is changed on a problem."""
    unknown = set(body) - {"name", "status", "sample_rate_hz"}
    if unknown:
        return f"Only name, status and sample_rate_hz can be changed, not {sorted(unknown)}."
    if "name" in body and (not isinstance(body["name"], str) or not body["name"].strip()):
        return "name must be a non-empty string."
    if "status" in body and body["status"] not in STATUSES:
        return f"status must be one of {list(STATUSES)}."
    if "sample_rate_hz" in body:
        rate = body["sample_rate_hz"]
        valid = isinstance(rate, int | float) and not isinstance(rate, bool)
        if not valid or not math.isfinite(rate) or not 0 < rate <= sensor.max_sample_rate_hz:
            return (
                f"sample_rate_hz must be a number above 0 and at most {sensor.max_sample_rate_hz}."
            )
    return None
