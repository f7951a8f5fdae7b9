import { apiFetch, getToken } from "./client";
import type { AuditEntry, Service } from "./types";

const enc = encodeURIComponent;

export async function listServices(slug: string, signal?: AbortSignal): Promise<Service[]> {
  const answer = await apiFetch<{ services: Service[] }>(`/api/v1/twins/${enc(slug)}/services`, { signal });
  return answer.services;
}

/** The gateway's request log, newest first: all of it (admins) or one twin's (its owners). */
export async function listAudit(limit = 100, signal?: AbortSignal, twin?: string): Promise<AuditEntry[]> {
  const answer = await apiFetch<{ entries: AuditEntry[] }>("/api/v1/gateway/audit", {
    query: { limit, twin },
    signal,
  });
  return answer.entries;
}

/** The service name the gateway gives a feature: lowercase, runs of other characters as "-". */
export function serviceNameOf(featureName: string): string {
  return featureName
    .toLowerCase()
    .replace(/[^a-z0-9]+/g, "-")
    .replace(/^-+|-+$/g, "");
}

/** The gateway URL of a request to a twin's service; `path` may carry a query string. */
export function serviceUrl(slug: string, service: string, path: string): string {
  const rest = path.replace(/^\/+/, "");
  return `/twins/${enc(slug)}/services/${enc(service)}/${rest}`;
}

export interface ServiceCall {
  url: string;
  status: number;
  statusText: string;
  ms: number;
  contentType: string;
  body: string;
  truncated: boolean;
  size: number;
}

export const MAX_SHOWN_CHARS = 100_000;

/** Send a request through the gateway and return the answer as is, whatever its status. */
export async function callService(
  slug: string,
  service: string,
  method: string,
  path: string,
  body: string | null,
  signal?: AbortSignal,
): Promise<ServiceCall> {
  const url = serviceUrl(slug, service, path);
  const headers: Record<string, string> = {};
  const token = getToken();
  if (token) headers.Authorization = `Bearer ${token}`;
  if (body !== null) headers["Content-Type"] = "application/json";
  const started = performance.now();
  const response = await fetch(url, { method, headers, body: body ?? undefined, signal });
  const text = await response.text();
  const ms = performance.now() - started;
  return {
    url,
    status: response.status,
    statusText: response.statusText,
    ms,
    contentType: response.headers.get("content-type") ?? "",
    body: text.length > MAX_SHOWN_CHARS ? text.slice(0, MAX_SHOWN_CHARS) : text,
    truncated: text.length > MAX_SHOWN_CHARS,
    size: text.length,
  };
}
