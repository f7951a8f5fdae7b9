import { apiFetch } from "./client";
import type { Schemas } from "./types";

export type ConnectorStatus = Schemas["ConnectorStatus"];

export type Connector = Schemas["ConnectorView"];

const enc = encodeURIComponent;

export async function listConnectors(slug: string, signal?: AbortSignal): Promise<Connector[]> {
  const answer = await apiFetch<{ connectors: Connector[] }>(`/api/v1/twins/${enc(slug)}/connectors`, { signal });
  return answer.connectors;
}

export type ConnectorAction = "start" | "stop" | "restart";

export async function connectorAction(slug: string, name: string, action: ConnectorAction): Promise<Connector> {
  return apiFetch<Connector>(`/api/v1/twins/${enc(slug)}/connectors/${enc(name)}/${action}`, { method: "POST" });
}
