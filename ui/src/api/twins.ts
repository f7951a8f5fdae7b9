import { apiFetch } from "./client";
import type { Device, RelationNode, Twin, TwinPage } from "./types";

const enc = encodeURIComponent;

export function listTwins(cursor: string | null, limit = 50, signal?: AbortSignal): Promise<TwinPage> {
  return apiFetch<TwinPage>("/api/v1/twins", { query: { limit, cursor }, signal });
}

export function getTwin(slug: string, signal?: AbortSignal): Promise<Twin> {
  return apiFetch<Twin>(`/api/v1/twins/${enc(slug)}`, { signal });
}

export function getRelations(
  slug: string,
  direction: "up" | "down",
  signal?: AbortSignal,
): Promise<RelationNode> {
  return apiFetch<RelationNode>(`/api/v1/twins/${enc(slug)}/relations`, {
    query: { direction, depth: 1 },
    signal,
  });
}

export async function listDevices(slug: string, signal?: AbortSignal): Promise<Device[]> {
  const answer = await apiFetch<{ devices: Device[] }>(`/api/v1/twins/${enc(slug)}/devices`, { signal });
  return answer.devices;
}
