// Deployments of twin packages and their lifecycle runs (issue 16).
import { apiFetch, apiRequest, getToken } from "./client";
import type { Schemas } from "./types";

export type DeploymentState = "planned" | "applying" | "created" | "running" | "stopped" | "terminated" | "failed";
export type ResourceType = "twin" | "device" | "processor" | "connector" | "service";
export type RunState = "queued" | "running" | "succeeded" | "failed" | "cancelled";

/** A deployment, its state as the app reads it (the API leaves it a string). */
export type Deployment = Omit<Schemas["Deployment"], "state"> & { state: DeploymentState };

/** One changed value of an update in a plan. */
export interface PlanChange {
  path: string;
  from: unknown;
  to: unknown;
}

/** A resource in a plan; an update's `changes` typed as the plan writes them (the API leaves
 * them open). */
export type PlanItem = Omit<Schemas["PlanEntry"], "changes"> & { changes?: PlanChange[] | null };

export interface Plan {
  create: PlanItem[];
  update: PlanItem[];
  delete: PlanItem[];
  keep: PlanItem[];
}

/** A lifecycle run, its state as the app reads it. */
export type Run = Omit<Schemas["Run"], "state"> & { state: RunState };

export type DeploymentRequest = Pick<Schemas["CreateBody"], "package" | "name" | "scope"> & {
  parameters: Record<string, unknown>;
};

/** The answer of a deploy or a reconfigure; device tokens (name -> token) shown once. (Its
 * schema is named twinlink__api__deployments__Applied in openapi.ts, beside the twins' own
 * Applied: not a name to depend on.) */
export interface CreateAnswer {
  deployment: Deployment;
  plan: Plan;
  device_tokens: Record<string, string>;
}

export const PHASES = ["create", "execute", "analyze", "evolve", "save", "terminate", "clean"] as const;

const enc = encodeURIComponent;
const BASE = "/api/v1/deployments";

export async function listDeployments(signal?: AbortSignal): Promise<Deployment[]> {
  const answer = await apiFetch<{ deployments: Deployment[] }>(BASE, { signal });
  return answer.deployments;
}

export function getDeployment(name: string, signal?: AbortSignal): Promise<Deployment> {
  return apiFetch<Deployment>(`${BASE}/${enc(name)}`, { signal });
}

/** What deploying would do; nothing is stored. */
export async function planDeployment(request: DeploymentRequest, signal?: AbortSignal): Promise<Plan> {
  const answer = await apiFetch<{ plan: Plan }>(BASE, { method: "POST", query: { dry_run: true }, json: request, signal });
  return answer.plan;
}

export function createDeployment(request: DeploymentRequest & { start?: boolean }): Promise<CreateAnswer> {
  return apiFetch<CreateAnswer>(BASE, { method: "POST", json: request });
}

/** Reconfigure: `parameters` to change (the others are kept), `package` another version of
 * the package ("<scope>/twins/<name>@<tag or digest>"). */
export type ChangeRequest = Schemas["ChangeBody"];

/** Reconfigure: the diff plan, applied unless `dryRun`. */
export function changeDeployment(name: string, change: ChangeRequest, dryRun: boolean): Promise<CreateAnswer> {
  return apiFetch<CreateAnswer>(`${BASE}/${enc(name)}`, { method: "PATCH", query: { dry_run: dryRun || undefined }, json: change });
}

export type Transition = "create" | "start" | "stop" | "terminate";

/** A lifecycle step; the answer is the deployment as it is after it (whatever its shape, the
 * page loads the deployment again). */
export function transition(name: string, step: Transition, purge = false): Promise<unknown> {
  return apiFetch<unknown>(`${BASE}/${enc(name)}/${step}`, {
    method: "POST",
    json: step === "terminate" ? { purge } : undefined,
  });
}

export function startRun(name: string, phase: string): Promise<Run> {
  return apiFetch<Run>(`${BASE}/${enc(name)}/runs`, { method: "POST", json: { phase } });
}

export async function listRuns(name: string, signal?: AbortSignal): Promise<Run[]> {
  const answer = await apiFetch<{ runs: Run[] }>(`${BASE}/${enc(name)}/runs`, { signal });
  return answer.runs;
}

export function cancelRun(id: number): Promise<unknown> {
  return apiFetch<unknown>(`/api/v1/runs/${id}/cancel`, { method: "POST" });
}

/** A run's log from byte `offset` on, and the run's state as the server saw it then. */
export async function readLog(id: number, offset = 0, signal?: AbortSignal): Promise<{ text: string; state: string | null }> {
  const response = await apiRequest(`/api/v1/runs/${id}/log`, { query: { offset }, accept: "text/plain", signal });
  return { text: await response.text(), state: response.headers.get("x-run-state") };
}

/** The WebSocket URL of a run's live log from byte `offset`. A browser cannot set headers on a WebSocket, so the
 * token goes in the first message (`authMessage`), as the live view's socket sends it: never
 * in the URL, where proxies log it. */
export function logSocketUrl(id: number, offset = 0, location: Location = window.location): string {
  const scheme = location.protocol === "https:" ? "wss:" : "ws:";
  const from = offset > 0 ? `?offset=${offset}` : "";
  return `${scheme}//${location.host}/api/v1/runs/${id}/log/ws${from}`;
}

export function authMessage(): string {
  return JSON.stringify({ op: "auth", token: getToken() ?? "" });
}

/** The final frame of the log socket: `{"state", "exit_code"}`. */
export function endFrame(data: string): { state: RunState; exit_code: number | null } | null {
  if (!data.startsWith("{")) return null;
  try {
    const parsed = JSON.parse(data) as Record<string, unknown>;
    if (typeof parsed.state === "string" && "exit_code" in parsed) {
      return { state: parsed.state as RunState, exit_code: typeof parsed.exit_code === "number" ? parsed.exit_code : null };
    }
  } catch {
    // a log chunk that happens to start with "{": shown as text
  }
  return null;
}

/** Whether a run may still change. */
export function isActive(run: Pick<Run, "state">): boolean {
  return run.state === "queued" || run.state === "running";
}
