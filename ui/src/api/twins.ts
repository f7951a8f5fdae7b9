import { apiFetch } from "./client";
import type { Device, RelationNode, Twin, TwinPage, TwinSummary } from "./types";

const enc = encodeURIComponent;

export function listTwins(cursor: string | null, limit = 50, signal?: AbortSignal): Promise<TwinPage> {
  return apiFetch<TwinPage>("/api/v1/twins", { query: { limit, cursor }, signal });
}

export function getTwin(slug: string, signal?: AbortSignal): Promise<Twin> {
  return apiFetch<Twin>(`/api/v1/twins/${enc(slug)}`, { signal });
}

/** A twin's children (down) or parents (up), `depth` levels deep. */
export function getRelations(
  slug: string,
  direction: "up" | "down",
  signal?: AbortSignal,
  depth = 1,
): Promise<RelationNode> {
  return apiFetch<RelationNode>(`/api/v1/twins/${enc(slug)}/relations`, {
    query: { direction, depth },
    signal,
  });
}

/** Every twin the user may see, page by page, stopping after `max`; `complete` says whether
 * the list ended before that. */
export async function listAllTwins(
  max: number,
  signal?: AbortSignal,
): Promise<{ items: TwinSummary[]; complete: boolean }> {
  const items: TwinSummary[] = [];
  let cursor: string | null = null;
  do {
    const page = await listTwins(cursor, Math.min(200, max - items.length), signal);
    items.push(...page.items);
    cursor = page.next_cursor;
  } while (cursor && items.length < max);
  return { items: items.slice(0, max), complete: cursor === null };
}

export interface DeviceList {
  devices: Device[];
  /** Where a command that names no device goes now (null: it must name one); absent from
   * servers before default devices. */
  default_device?: string | null;
}

export function getDeviceList(slug: string, signal?: AbortSignal): Promise<DeviceList> {
  return apiFetch<DeviceList>(`/api/v1/twins/${enc(slug)}/devices`, { signal });
}

export async function listDevices(slug: string, signal?: AbortSignal): Promise<Device[]> {
  return (await getDeviceList(slug, signal)).devices;
}
