"""A twin's `interface` as a W3C WoT Thing Description 1.1, and the TD's validation.

Mapping (docs/formats.md, "WoT Thing Description"):

- a signal becomes a TD property, `readOnly` and `observable`: a signal has a current value
  (`GET .../streams/telemetry/latest`) and a live feed (`/api/v1/live`, MQTT), which is what
  a WoT property is; a WoT event is an occurrence without a current value. Only a signal
  whose name a property of the interface already takes becomes an event (with the same
  forms), because a TD has one namespace for properties;
- a property becomes a TD property, not `observable` (reported values are read, not
  streamed), `readOnly` unless it is `writable` (then `writeproperty` is the PATCH of the
  desired values);
- a command becomes an action whose `input` is an object schema of its parameters.

Every form points at this instance's real endpoints (from ExportContext) and needs a user
token (`bearer_sc`); the MQTT forms, given for a broker of your own (external mode), need the
broker's credentials.
The import is in _wot_import.py.
"""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path
from typing import Any
from urllib.parse import quote

from jsonschema import Draft7Validator  # type: ignore[import-untyped]

from twinlink.formats._wot_import import import_wot
from twinlink.formats.context import ExportContext

__all__ = ["MEDIA_TYPE", "TD_CONTEXT", "export_wot", "import_wot", "validate_wot"]

MEDIA_TYPE = "application/td+json"
TD_CONTEXT = "https://www.w3.org/2022/wot/td/v1.1"
MQV = "https://www.w3.org/2019/wot/mqtt#"  # the MQTT binding's vocabulary (wot-binding-templates)
# Our own terms (the interface's policies) need an IRI; a URN names them without pretending
# to be a page that can be fetched.
TWINLINK_NS = "urn:twinlink:interface#"
POLICY_TERM = "twinlink:interface"
DEVICE_REL = "twinlink:deviceIngest"  # links to where the twin's devices send telemetry
SCHEMA_FILE = Path(__file__).parent / "schemas" / "td-json-schema-validation.json"
TELEMETRY = "telemetry"  # the default stream, where devices send unless they name another
_TYPES = {"number": "number", "integer": "integer", "bool": "boolean", "string": "string"}
_JSON = "application/json"
# TD terms an imported entry may carry (_wot_import.py keeps them): exported as they are.
_PASSED = ("@type", "title", "enum", "const", "format", "exclusiveMinimum", "exclusiveMaximum")
_PASSED_ACTION = ("@type", "title", "output")


def export_wot(document: dict[str, Any], ctx: ExportContext) -> dict[str, Any]:
    """The TD 1.1 of a twin, from the document a reader gets."""
    interface = document.get("interface") or {}
    mqtt = ctx.mqtt_url is not None and ctx.mqtt_external
    context: list[Any] = [TD_CONTEXT, {"twinlink": TWINLINK_NS}]
    if ctx.mqtt_url:
        context[1]["mqv"] = MQV
    td: dict[str, Any] = {"@context": context, "@type": "Thing"}
    global_id = document.get("id") or document.get("dt-id")
    td["id"] = str(global_id) if global_id else ctx.twin_url
    td["title"] = str(document.get("name") or ctx.slug)
    if document.get("description"):
        td["description"] = str(document["description"])
    td["securityDefinitions"] = _security_definitions(mqtt)
    td["security"] = ["bearer_sc"]
    td["links"] = _links(document, ctx)
    properties, events = _properties(interface, ctx)
    td["properties"] = properties
    td["actions"] = {c["name"]: _action(c, ctx) for c in interface.get("commands") or []}
    td["events"] = events
    policies = {
        key: interface[key]
        for key in ("default_device", "unknown_signals", "out_of_range")
        if key in interface
    }
    if policies:
        td[POLICY_TERM] = policies
    return td


def validate_wot(data: dict[str, Any]) -> list[str]:
    """Problems of a TD against the W3C TD JSON Schema and the rules it cannot state."""
    problems = [
        f"{_where(e.absolute_path)}: {e.message}"
        for e in sorted(_validator().iter_errors(data), key=lambda e: list(map(str, e.path)))
    ]
    defined = data.get("securityDefinitions") if isinstance(data, dict) else None
    if isinstance(defined, dict):
        for path, names in _security_uses(data):
            problems.extend(
                f"{path}: security scheme {name!r} is not in securityDefinitions"
                for name in names
                if name not in defined
            )
    return problems


@cache
def _validator() -> Draft7Validator:
    return Draft7Validator(json.loads(SCHEMA_FILE.read_text(encoding="utf-8")))


def _where(path: Any) -> str:
    return "/".join(str(p) for p in path) or "(the TD)"


def _security_uses(td: dict[str, Any]) -> list[tuple[str, list[str]]]:
    """Each `security` of the TD and of its forms, with the names it uses."""
    uses: list[tuple[str, Any]] = [("security", td.get("security"))]
    for kind in ("properties", "actions", "events"):
        affordances = td.get(kind)
        if not isinstance(affordances, dict):
            continue
        for name, affordance in affordances.items():
            forms = affordance.get("forms") if isinstance(affordance, dict) else None
            for i, form in enumerate(forms if isinstance(forms, list) else []):
                if isinstance(form, dict) and "security" in form:
                    uses.append((f"{kind}/{name}/forms/{i}/security", form["security"]))
    out = []
    for path, value in uses:
        names = [value] if isinstance(value, str) else value if isinstance(value, list) else []
        out.append((path, [n for n in names if isinstance(n, str)]))
    return out


def _security_definitions(mqtt: bool) -> dict[str, Any]:
    schemes: dict[str, Any] = {
        "bearer_sc": {
            "scheme": "bearer",
            "in": "header",
            "name": "Authorization",
            "description": (
                "A twinlink user token (tl_...) as `Authorization: Bearer <token>`: sign in "
                "with POST /api/v1/auth/login, or make an API token (POST /api/v1/tokens). "
                "Reading needs a role on the twin (or its public part); writing properties "
                "and invoking actions need an editor."
            ),
        }
    }
    if mqtt:
        schemes["broker_sc"] = {
            "scheme": "basic",
            "description": (
                "MQTT: a user name and password of the broker's own, which twinlink neither "
                "issues nor checks; the broker's access list must let the user read the "
                "twin's topics."
            ),
        }
    return schemes


def _links(document: dict[str, Any], ctx: ExportContext) -> list[dict[str, Any]]:
    """The twin's document, where its devices send (the device's side, which no TD operation
    describes: a TD's operations are a consumer's), and the twins it relates to by URL."""
    links: list[dict[str, Any]] = [
        {"rel": "describedby", "href": ctx.twin_url, "type": "application/yaml"},
        {"rel": DEVICE_REL, "href": f"{ctx.api_url}/device/samples", "type": _JSON},
        {"rel": DEVICE_REL, "href": f"{_ws_base(ctx.api_url)}/device/ws", "type": _JSON},
    ]
    if ctx.mqtt_url:
        topic = f"{ctx.mqtt_topic_prefix}/{ctx.slug}/{{device}}/{TELEMETRY}"
        links.append({"rel": DEVICE_REL, "href": ctx.mqtt_url, "type": _JSON, "mqv:topic": topic})
    for relation in document.get("relations") or []:
        if not isinstance(relation, dict):
            continue
        other = relation.get("id") or relation.get("dt-id")
        if isinstance(other, str) and other.startswith(("http://", "https://")):
            links.append({"rel": str(relation.get("relationType") or "related"), "href": other})
    return links


def _properties(
    interface: dict[str, Any], ctx: ExportContext
) -> tuple[dict[str, Any], dict[str, Any]]:
    properties: dict[str, Any] = {
        p["name"]: _property(p, interface, ctx) for p in interface.get("properties") or []
    }
    events: dict[str, Any] = {}
    # An imported TD's events whose names its signals took (_wot_import.py), then the signals.
    for kept in interface.get("events") or []:
        if isinstance(kept, dict) and kept.get("name"):
            events[str(kept["name"])] = _event(kept, ctx)
    for signal in interface.get("signals") or []:
        name = signal["name"]
        if name in properties:  # a property took the name: an event keeps the signal
            events[name] = _event(signal, ctx)
        else:
            properties[name] = {
                **_describe(signal),
                **_schema(signal),
                "readOnly": True,
                "observable": True,
                "forms": _signal_forms(name, ctx, ("observeproperty", "unobserveproperty")),
            }
    return properties, events


def _event(signal: dict[str, Any], ctx: ExportContext) -> dict[str, Any]:
    forms = _signal_forms(str(signal["name"]), ctx, ("subscribeevent", "unsubscribeevent"))
    return {**_describe(signal), "data": _schema(signal), "forms": forms}


def _signal_forms(name: str, ctx: ExportContext, observe: tuple[str, str]) -> list[Any]:
    stream = f"{ctx.api_url}/twins/{quote(ctx.slug)}/streams/{TELEMETRY}"
    forms: list[dict[str, Any]] = []
    if observe[0] == "observeproperty":
        latest = f"{stream}/latest?signals={quote(name, safe='')}"
        forms.append({"op": "readproperty", "href": latest, "contentType": _JSON})
    forms.append({"op": list(observe), "href": _live_url(ctx), "contentType": _JSON})
    if ctx.mqtt_url and ctx.mqtt_external:
        topic = f"{ctx.mqtt_topic_prefix}/{ctx.slug}/+/{TELEMETRY}"
        forms.append(
            {
                "op": observe[0],
                "href": ctx.mqtt_url,
                "contentType": _JSON,
                "mqv:filter": topic,
                "mqv:controlPacket": "subscribe",
                "mqv:qos": "1",
                "security": ["broker_sc"],
            }
        )
    return forms


def _live_url(ctx: ExportContext) -> str:
    """The live WebSocket: every instance serves it beside its API (docs/protocol.md)."""
    return ctx.ws_url or f"{_ws_base(ctx.api_url)}/live"


def _ws_base(api_url: str) -> str:
    scheme, sep, rest = api_url.partition("://")
    return f"{'wss' if scheme == 'https' else 'ws'}{sep}{rest}"


def _property(prop: dict[str, Any], interface: dict[str, Any], ctx: ExportContext) -> Any:
    properties = f"{ctx.api_url}/twins/{quote(ctx.slug)}/devices/{{device}}/properties"
    writable = prop.get("writable") is True
    forms: list[dict[str, Any]] = [{"op": "readproperty", "href": properties, "contentType": _JSON}]
    if writable:
        forms.append(
            {
                "op": "writeproperty",
                "href": f"{properties}/desired",
                "contentType": _JSON,
                "htv:methodName": "PATCH",
            }
        )
    device: dict[str, Any] = {
        "type": "string",
        "description": "The device that reports the property (GET .../devices lists them).",
    }
    if interface.get("default_device"):
        device["default"] = str(interface["default_device"])
    return {
        **_describe(prop),
        **_schema(prop),
        "readOnly": not writable,
        "observable": False,
        "uriVariables": {"device": device},
        "forms": forms,
    }


def _action(command: dict[str, Any], ctx: ExportContext) -> dict[str, Any]:
    action: dict[str, Any] = _describe(command)
    action.update({k: command[k] for k in _PASSED_ACTION if k in command})
    parameters = command.get("parameters") or []
    if parameters:
        action["input"] = {
            "type": "object",
            "properties": {p["name"]: {**_describe(p), **_schema(p)} for p in parameters},
            "required": [p["name"] for p in parameters if p.get("required") is True],
        }
    action["safe"] = False
    action["idempotent"] = False
    href = f"{ctx.api_url}/twins/{quote(ctx.slug)}/commands"
    action["forms"] = [
        {"op": "invokeaction", "href": href, "contentType": _JSON, "htv:methodName": "POST"}
    ]
    return action


def _describe(entry: dict[str, Any]) -> dict[str, Any]:
    text = entry.get("description")
    return {"description": str(text)} if text else {}


def _schema(entry: dict[str, Any]) -> dict[str, Any]:
    """The data schema of a signal, property or parameter: type, range, unit; or the TD
    schema an import kept (`schema`: an object, an array), and the TD terms it kept."""
    kept = {k: entry[k] for k in _PASSED if k in entry}
    if isinstance(entry.get("schema"), dict):
        return {**entry["schema"], **kept}
    schema: dict[str, Any] = {"type": _TYPES.get(str(entry.get("type") or "number"), "string")}
    schema.update(kept)
    if entry.get("min") is not None:
        schema["minimum"] = entry["min"]
    if entry.get("max") is not None:
        schema["maximum"] = entry["max"]
    if entry.get("unit"):
        schema["unit"] = str(entry["unit"])
    if entry.get("default") is not None:  # parameters only
        schema["default"] = entry["default"]
    return schema
