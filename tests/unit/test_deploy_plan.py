"""Plans: what a create makes, and what a reconfigure creates, updates, deletes and keeps."""

from __future__ import annotations

from typing import Any

from twinlink.deploy.plan import MASK, Resource, canonical, plan_change, plan_create, shown


def fingerprint(spec: dict[str, Any]) -> str:
    return canonical(spec).hex()


def entry(r: Resource) -> dict[str, Any]:
    return {"type": r.type, "name": r.name, "spec": shown(r), "fingerprint": fingerprint(r.spec)}


TWIN = Resource("twin", "rig", {"version": "1.0", "name": "rig"})
DEV = Resource("device", "sap", {"name": "sap", "description": ""})
LOW = Resource("processor", "smooth", {"name": "smooth", "params": {"cutoff_hz": 5}})
EXP = Resource("processor", "sum", {"name": "sum", "params": {"expression": "a"}})


def test_a_create_makes_everything() -> None:
    plan = plan_create([TWIN, DEV, LOW])
    view = plan.view()
    assert [(c["type"], c["name"]) for c in view["create"]] == [
        ("twin", "rig"), ("device", "sap"), ("processor", "smooth"),
    ]  # fmt: skip
    assert view["update"] == view["delete"] == view["keep"] == []


def test_a_change_keeps_updates_creates_and_deletes() -> None:
    journal = [entry(TWIN), entry(DEV), entry(LOW), entry(EXP)]
    low2 = Resource("processor", "smooth", {"name": "smooth", "params": {"cutoff_hz": 2}})
    new = Resource("processor", "peak", {"name": "peak", "params": {}})
    dev2 = Resource("device", "sap", {"name": "sap", "description": "a new text"})
    resources = [TWIN, dev2, low2, new]
    plan = plan_change(journal, resources, {r.key: fingerprint(r.spec) for r in resources})
    view = plan.view()
    assert view["keep"] == [{"type": "twin", "name": "rig"}, {"type": "device", "name": "sap"}]
    assert view["update"] == [
        {"type": "processor", "name": "smooth",
         "changes": [{"path": "params.cutoff_hz", "from": 5, "to": 2}]},
    ]  # fmt: skip
    assert [c["name"] for c in view["create"]] == ["peak"]
    assert view["delete"] == [{"type": "processor", "name": "sum"}]


def test_secrets_are_masked_and_their_change_still_seen() -> None:
    svc = Resource("service", "api", {"name": "api", "base_url": "http://x",
                                      "auth": {"method": "basic", "username": "u",
                                               "password": "hunter2"}})  # fmt: skip
    assert shown(svc)["auth"] == {"method": "basic", "username": MASK, "password": MASK}
    assert "hunter2" not in str(plan_create([svc]).view())
    changed = Resource("service", "api", {**svc.spec, "auth": {**svc.spec["auth"],
                                                               "password": "other"}})  # fmt: skip
    plan = plan_change([entry(svc)], [changed], {changed.key: fingerprint(changed.spec)})
    assert plan.view()["update"][0]["changes"] == [{"path": "(secret)", "from": MASK, "to": MASK}]


def test_secret_parameter_values_are_hidden_wherever_written_in() -> None:
    from twinlink.deploy.secrets import hidden_values, secret_names, split

    schema = {"properties": {"pw": {"type": "string", "writeOnly": True},
                             "pin": {"type": "integer", "format": "password"},
                             "user": {"type": "string"}}}  # fmt: skip
    names = secret_names(schema)
    assert names == {"pw", "pin"}
    params = {"pw": "hunter2", "pin": 1234, "user": "u"}
    assert split(params, names) == ({"pw": MASK, "pin": MASK, "user": "u"},
                                     {"pw": "hunter2", "pin": 1234})  # fmt: skip
    hidden = hidden_values(params, names)
    svc = Resource("processor", "p", {"url": "http://x/hunter2/y", "n": 1234, "u": "u"})
    assert shown(svc, hidden) == {"url": f"http://x/{MASK}/y", "n": MASK, "u": "u"}
    assert "hunter2" not in str(plan_create([svc], hidden).view())
