"""A twin to run services against, on one backend's stores (`_storage.Stores`): its owner
`alice`, a viewer `bob`, `carol` with no role, a device `plc`, and a registry in front of the
metadata store. `fresh()` gives another registry and device hub on the same stores, as a
restarted server has: whatever a service finds then, it found in the stores."""

from __future__ import annotations

import secrets
from dataclasses import dataclass

from tests.unit._storage import Stores
from twinlink.auth.rights import Principal
from twinlink.domain.records import Device, SearchRow, TwinRecord, TwinWrite
from twinlink.ingest.sessions import DeviceHub
from twinlink.registry.service import RegistryService

T = 1_704_067_200 * 10**9  # 2024-01-01T00:00:00Z in ns
SLUG = "rig"


@dataclass(slots=True)
class Setting:
    stores: Stores
    registry: RegistryService
    hub: DeviceHub
    owner: Principal
    viewer: Principal
    stranger: Principal
    twin: TwinRecord
    device: Device

    def fresh(self) -> Setting:
        registry = RegistryService(self.stores.metadata, "http://x")
        return Setting(self.stores, registry, DeviceHub(), self.owner, self.viewer,
                       self.stranger, self.twin, self.device)  # fmt: skip


async def setting(stores: Stores) -> Setting:
    """A private twin (only people with a role on it see it) with one device."""
    store = stores.metadata
    alice, bob, carol = [
        await store.create_user(n, None, False, [], T) for n in ("alice", "bob", "carol")
    ]
    write = TwinWrite(
        slug=SLUG, dt_id=f"urn:{SLUG}", name=SLUG, created_ns=T, modified_ns=T,
        parts={"crew": {"name": SLUG}}, edges=[],
        search_rows=[SearchRow("crew", None, SLUG, "", [], "")], owner_user_id=alice.id,
    )  # fmt: skip
    [twin] = await store.save_twins([write])
    await store.set_role(twin.id, bob.id, "viewer")
    device = await store.create_device(twin.id, "plc", "", secrets.token_bytes(32), "tl_d", T)
    registry = RegistryService(store, "http://x")
    return Setting(stores, registry, DeviceHub(), Principal(alice), Principal(bob),
                   Principal(carol), twin, device)  # fmt: skip
