"""Answers of /healthz, /readyz, /api/v1/mqtt and a device's batch (its ack)."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import BaseModel, Field


class Healthy(BaseModel):
    status: Literal["ok"]
    version: str


class Ready(BaseModel):
    """The store answered its ping and the bus is usable, within TWINLINK_READY_TIMEOUT_S."""

    status: Literal["ready"]
    version: str


class MqttStatus(BaseModel):
    state: str
    since_ns: int
    errors: dict[str, int]
    error_count: int
    last_error: str | None
    last_error_ns: int | None
    mode: Literal["embedded", "external", "off"] | str
    address: str | None
    clients: int
    connects: int
    refused: dict[str, int]
    messages: int
    received: dict[str, int] = Field(description="messages by kind")
    samples: int
    sent: int


class Ack(BaseModel):
    """A batch's ack (docs/protocol.md): sent once the accepted samples are stored."""

    type: Literal["ack"]
    seq: Any = Field(description="the batch's `seq`, as sent")
    accepted: int
    rejected: list[dict[str, Any]] = Field(description="the first samples refused, and why")
    rejected_count: int
    server_timed: int = Field(description="samples without a time, timed by the server")
    dropped: int
    duplicate: bool = Field(description="a batch already stored (same device and seq)")


# The batch a device sends (docs/protocol.md, "Samples and batches"), for the description
# only: the route reads the body itself, exactly (integers beyond 64 bits are refused).
BATCH_BODY: dict[str, Any] = {
    "requestBody": {
        "required": True,
        "content": {
            "application/json": {
                "schema": {
                    "type": "object",
                    "required": ["seq", "samples"],
                    "properties": {
                        "seq": {"type": "integer", "minimum": 0, "maximum": 2**63 - 1},
                        "stream": {"type": "string", "pattern": "^[a-z][a-z0-9_-]{0,63}$"},
                        "time_unit": {"enum": ["ns", "us", "ms", "s"]},
                        "samples": {
                            "type": "array",
                            "maxItems": 100_000,
                            "items": {
                                "type": "object",
                                "required": ["values"],
                                "properties": {
                                    "time": {"type": ["integer", "string"]},
                                    "values": {"type": "object"},
                                },
                            },
                        },
                    },
                }
            }
        },
    }
}
