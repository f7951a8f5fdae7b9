// Which device the Commands tab sends to. A twin with several devices needs one named: the
// tab preselects the one a command naming none would go to, so Send works at once, and it
// never sends without one. The server's objections speak of its API (`device`); here they
// speak of the Device list.
import { ApiError } from "../../api/client";
import type { Device } from "../../api/types";

export const CHOOSE_DEVICE = "Choose the device to send to in the Device list above.";

/** The device to preselect: the server's choice when it names one of the devices (where a
 * command that names none goes), else the twin's declared `default_device`, else the only
 * connected device, else the only device; undefined when the user has to choose. */
export function preselectDevice(devices: Device[], declared: string | undefined, serverChoice?: string | null): string | undefined {
  const names = new Set(devices.map((d) => d.name));
  if (serverChoice && names.has(serverChoice)) return serverChoice;
  if (declared && names.has(declared)) return declared;
  const connected = devices.filter((d) => d.connected);
  if (connected.length === 1) return connected[0]?.name;
  return devices.length === 1 ? devices[0]?.name : undefined;
}

/** An error of a send, phrased for this page. */
export function forThisPage(error: unknown): Error {
  if (!(error instanceof Error)) return new Error(String(error));
  const suffix = "; name one with `device`";
  if (error instanceof ApiError && error.detail.endsWith(suffix)) {
    return new ApiError(error.status, `${error.detail.slice(0, -suffix.length)}. ${CHOOSE_DEVICE}`, error.problem);
  }
  return error;
}
