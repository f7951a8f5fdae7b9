import { apiFetch } from "./client";

export interface ConnectorStatus {
  state: string;
  since_ns: number;
  last_message_ns: number | null;
  messages: number;
  samples: number;
  rejected: number;
  commands: number;
  errors: Record<string, number>;
  error_count: number;
  last_error: string | null;
  last_error_ns: number | null;
  address?: string;
}

export interface Connector {
  name: string;
  twin: string;
  kind: string;
  device: string;
  enabled: boolean;
  config: Record<string, unknown>;
  status: ConnectorStatus;
}

const enc = encodeURIComponent;

export async function listConnectors(slug: string, signal?: AbortSignal): Promise<Connector[]> {
  const answer = await apiFetch<{ connectors: Connector[] }>(`/api/v1/twins/${enc(slug)}/connectors`, { signal });
  return answer.connectors;
}

export type ConnectorAction = "start" | "stop" | "restart";

export async function connectorAction(slug: string, name: string, action: ConnectorAction): Promise<Connector> {
  return apiFetch<Connector>(`/api/v1/twins/${enc(slug)}/connectors/${enc(name)}/${action}`, { method: "POST" });
}
