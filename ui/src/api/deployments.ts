// Deployments of twin packages and their lifecycle runs (issue 16). Typed here by hand from
// the shared design until openapi.ts is regenerated with these routes.
import { apiFetch, apiRequest, getToken } from "./client";

export type DeploymentState = "planned" | "applying" | "created" | "running" | "stopped" | "terminated" | "failed";
export type ResourceType = "twin" | "device" | "processor" | "connector" | "service";

export interface Deployment {
  id: number;
  name: string;
  /** The pinned ref of the package: lib:<scope>/twins/<name>@sha256:... */
  package: string;
  /** The package as it was asked for ("tingen-rig@1.0.0"). */
  package_ref: string;
  parameters: Record<string, unknown>;
  state: DeploymentState;
  twin: string;
  resources: {
    twin?: string | null;
    devices?: string[];
    processors?: string[];
    connectors?: string[];
    services?: string[];
  };
  created_by: string | null;
  created_ns: number;
  updated_ns: number;
  error: string | null;
}

export interface PlanChange {
  path: string;
  from: unknown;
  to: unknown;
}

export interface PlanItem {
  type: ResourceType;
  name: string;
  spec?: unknown;
  changes?: PlanChange[];
}

export interface Plan {
  create: PlanItem[];
  update: PlanItem[];
  delete: PlanItem[];
  keep: PlanItem[];
}

export type RunState = "queued" | "running" | "succeeded" | "failed" | "cancelled";

export interface Run {
  id: number;
  deployment: string;
  twin?: string;
  phase: string;
  state: RunState;
  exit_code: number | null;
  started_by: string | null;
  created_ns: number;
  started_ns: number | null;
  ended_ns: number | null;
  node: string | null;
  error: string | null;
  timeout_s?: number;
  memory_mb?: number;
}

export interface DeploymentRequest {
  package: string;
  name: string;
  parameters: Record<string, unknown>;
  scope?: string;
}

export interface CreateAnswer {
  deployment: Deployment;
  plan: Plan;
  /** device name -> token, shown once. */
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

export interface ChangeRequest {
  /** Those to change; the others are kept. */
  parameters?: Record<string, unknown>;
  /** Another version of the package: "<scope>/twins/<name>@<tag or digest>". */
  package?: string;
}

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

/** The WebSocket URL of a run's live log. A browser cannot set headers on a WebSocket, so the
 * token goes in the first message (`authMessage`), as the live view's socket sends it: never
 * in the URL, where proxies log it. */
export function logSocketUrl(id: number, location: Location = window.location): string {
  const scheme = location.protocol === "https:" ? "wss:" : "ws:";
  return `${scheme}//${location.host}/api/v1/runs/${id}/log/ws`;
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
