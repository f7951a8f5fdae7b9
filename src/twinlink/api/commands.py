"""/api/v1/twins/{slug}/commands (people send commands and read the log) and
/api/v1/device/commands (a device without a WebSocket fetches commands and sends results)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Depends, Query, Request
from pydantic import BaseModel, Field

from twinlink.api.deps import Caller
from twinlink.api.devices import ThisDevice
from twinlink.api.models.commands import CommandList, CommandView, PendingCommands, ResultAck
from twinlink.api.models.problem import problems
from twinlink.api.responses import JSONAnswer
from twinlink.api.routing import ExactJsonRoute
from twinlink.commands import CommandService
from twinlink.commands.service import MAX_LIST, MAX_TIMEOUT_S
from twinlink.domain.commands import STATES

router = APIRouter(
    prefix="/api/v1",
    tags=["commands"],
    route_class=ExactJsonRoute,
    responses=problems(401, 404, 422, 503),
)
# Sending a command or a result stores it: a full disk refuses it.
STORING = problems(409, 507)
MAX_POLL_S = 60.0


async def command_service(request: Request) -> CommandService:
    return request.app.state.services.commands  # type: ignore[no-any-return]


Commands = Annotated[CommandService, Depends(command_service)]


class NewCommand(BaseModel):
    name: str = Field(description="a command of the twin's interface (any name if it has none)")
    args: dict[str, Any] | None = Field(None, description="argument name -> value")
    device: str | None = Field(None, description="the device; may be left out if there is one")
    timeout_s: float | None = Field(
        None, gt=0, le=MAX_TIMEOUT_S, description="seconds until it expires [server default]"
    )
    queue: bool = Field(False, description="keep it for an offline device until it connects")
    wait: bool = Field(True, description="answer when it has finished, not at once")


class CommandResult(BaseModel):
    status: Literal["succeeded", "failed"]
    result: Any = Field(None, description="any JSON value")
    error: str | None = None


@router.post(
    "/twins/{slug}/commands",
    summary="Send a command to a device (editors); 200 when finished, 202 while underway",
    response_class=JSONAnswer,
    response_model=CommandView,
    responses={
        202: {
            "model": CommandView,
            "description": "Sent (or queued) and not finished yet: poll its id",
        },
        **problems(403),
        **STORING,
    },
)
async def send_command(
    slug: str, body: NewCommand, caller: Caller, commands: Commands
) -> JSONAnswer:
    record = await commands.send(
        caller, slug, body.name, body.args, body.device, body.timeout_s, body.queue, body.wait
    )
    return JSONAnswer(record.view(slug), status_code=202 if record.is_open else 200)


@router.get(
    "/twins/{slug}/commands",
    summary="The command log of a twin, newest first (viewers)",
    response_class=JSONAnswer,
    response_model=CommandList,
    responses=problems(403),
)
async def list_commands(
    slug: str,
    caller: Caller,
    commands: Commands,
    state: Annotated[str | None, Query(description=f"one of {', '.join(STATES)}")] = None,
    name: Annotated[str | None, Query(description="only commands of this name")] = None,
    device: Annotated[str | None, Query(description="only commands to this device")] = None,
    limit: Annotated[int, Query(ge=1, le=MAX_LIST)] = 100,
) -> JSONAnswer:
    found = await commands.list_commands(caller, slug, state, name, device, limit)
    return JSONAnswer({"commands": [r.view(slug) for r in found]})


@router.get(
    "/twins/{slug}/commands/{command_id}",
    summary="One command and its state (viewers)",
    response_class=JSONAnswer,
    response_model=CommandView,
    responses=problems(403),
)
async def get_command(slug: str, command_id: str, caller: Caller, commands: Commands) -> JSONAnswer:
    return JSONAnswer((await commands.get(caller, slug, command_id)).view(slug))


@router.get(
    "/device/commands",
    summary="Pending commands for this device, waiting up to `wait` s; they count as "
    "delivered (device token)",
    response_class=JSONAnswer,
    response_model=PendingCommands,
    responses=problems(507),
)
async def poll_commands(
    device: ThisDevice,
    commands: Commands,
    wait: Annotated[float, Query(ge=0, le=MAX_POLL_S, description="seconds to wait")] = 0,
) -> JSONAnswer:
    found = await commands.poll(device, wait)
    pending = [{k: v for k, v in r.message().items() if k != "type"} for r in found]
    return JSONAnswer({"commands": pending})


@router.post(
    "/device/commands/{command_id}/result",
    summary="The result of a command (device token)",
    response_class=JSONAnswer,
    response_model=ResultAck,
    responses=STORING,
)
async def post_result(
    command_id: str, body: CommandResult, device: ThisDevice, commands: Commands
) -> JSONAnswer:
    record = await commands.record_result(device, command_id, body.status, body.result, body.error)
    return JSONAnswer({"id": record.id, "state": record.state, "late_status": record.late_status})
