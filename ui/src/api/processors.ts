// Processors, blueprints and FMUs of a twin (docs/processors.md).
import { apiFetch } from "./client";
import type { Schemas } from "./types";

const enc = encodeURIComponent;

/** A JSON schema as pydantic emits it; only the keywords the form reads are typed. */
export interface JsonSchema {
  type?: string | string[];
  title?: string;
  description?: string;
  default?: unknown;
  enum?: unknown[];
  const?: unknown;
  properties?: Record<string, JsonSchema>;
  required?: string[];
  additionalProperties?: boolean | JsonSchema;
  items?: JsonSchema;
  anyOf?: JsonSchema[];
  oneOf?: JsonSchema[];
  allOf?: JsonSchema[];
  $ref?: string;
  $defs?: Record<string, JsonSchema>;
  definitions?: Record<string, JsonSchema>;
  minimum?: number;
  maximum?: number;
  exclusiveMinimum?: number;
  exclusiveMaximum?: number;
  minLength?: number;
  maxLength?: number;
  minItems?: number;
  maxItems?: number;
  format?: string;
  [keyword: string]: unknown;
}

export type Blueprint = Omit<Schemas["Blueprint"], "params_schema"> & { params_schema?: JsonSchema | null };

export type ProcessorState = "starting" | "running" | "backoff" | "stopping" | "stopped" | "failed" | "finished" | string;

export type InputMap = Schemas["InputMap"];

export type Rates = Schemas["Rates"];

export type Percentiles = Schemas["Percentiles"];

export type ProcessorStats = Schemas["ProcessorStats"];

/** A processor as the API answers it (`ProcessorView`), with the fields the API leaves open
 * (`running`: what the worker says of itself) typed as the app reads them. */
export interface Processor extends Omit<Schemas["ProcessorView"], "running" | "state"> {
  state: ProcessorState;
  running: { inputs?: string[]; outputs?: string[]; describe?: Record<string, unknown> };
}

/** What POST .../processors takes; fields left out get the server's defaults. */
export type ProcessorSpec = Schemas["ProcessorSpec"];

export type ProcessorEvent = Schemas["ProcessorEvent"];

export type LogLine = Schemas["LogLine"];

export interface FmuVariable {
  name: string;
  value_reference: number;
  causality: string;
  variability: string;
  type: string;
  initial?: string | null;
  unit?: string | null;
  start?: number | boolean | string | null;
  min?: number | null;
  max?: number | null;
  description?: string | null;
  shape?: number[];
}

export interface Fmu {
  name: string;
  sha256: string;
  size: number;
  uploaded_ns: number;
  fmi_version?: string;
  model_name?: string;
  description?: string | null;
  co_simulation?: boolean;
  model_exchange?: boolean;
  variables?: FmuVariable[];
  [key: string]: unknown;
}

export interface StreamSignal {
  name: string;
  kind: string;
  count: number;
}

export type StreamSummary = Schemas["StreamInfo"];

const twinPath = (slug: string) => `/api/v1/twins/${enc(slug)}`;
const processorPath = (slug: string, name: string) => `${twinPath(slug)}/processors/${enc(name)}`;

export async function listBlueprints(signal?: AbortSignal): Promise<Blueprint[]> {
  return (await apiFetch<{ blueprints: Blueprint[] }>("/api/v1/blueprints", { signal })).blueprints;
}

export function getBlueprint(name: string, signal?: AbortSignal): Promise<Blueprint> {
  return apiFetch<Blueprint>(`/api/v1/blueprints/${enc(name)}`, { signal });
}

export async function listProcessors(slug: string, signal?: AbortSignal): Promise<Processor[]> {
  return (await apiFetch<{ processors: Processor[] }>(`${twinPath(slug)}/processors`, { signal })).processors;
}

export function getProcessor(slug: string, name: string, signal?: AbortSignal): Promise<Processor> {
  return apiFetch<Processor>(processorPath(slug, name), { signal });
}

export function createProcessor(slug: string, spec: ProcessorSpec): Promise<Processor> {
  return apiFetch<Processor>(`${twinPath(slug)}/processors`, { method: "POST", json: spec });
}

export function updateProcessor(slug: string, name: string, changes: Partial<ProcessorSpec>): Promise<Processor> {
  return apiFetch<Processor>(processorPath(slug, name), { method: "PATCH", json: changes });
}

export type ProcessorAction = "start" | "stop" | "restart";

export function processorAction(slug: string, name: string, action: ProcessorAction): Promise<Processor> {
  return apiFetch<Processor>(`${processorPath(slug, name)}/${action}`, { method: "POST" });
}

export function deleteProcessor(slug: string, name: string): Promise<void> {
  return apiFetch<void>(processorPath(slug, name), { method: "DELETE" });
}

export async function listProcessorEvents(slug: string, name: string, signal?: AbortSignal): Promise<ProcessorEvent[]> {
  const path = `${processorPath(slug, name)}/events`;
  return (await apiFetch<{ events: ProcessorEvent[] }>(path, { query: { limit: 100 }, signal })).events;
}

export async function getProcessorLogs(slug: string, name: string, signal?: AbortSignal): Promise<LogLine[]> {
  return (await apiFetch<{ lines: LogLine[] }>(`${processorPath(slug, name)}/logs`, { signal })).lines;
}

export async function listFmus(slug: string, signal?: AbortSignal): Promise<Fmu[]> {
  return (await apiFetch<{ fmus: Fmu[] }>(`${twinPath(slug)}/fmus`, { signal })).fmus;
}

export function getFmu(slug: string, name: string, signal?: AbortSignal): Promise<Fmu> {
  return apiFetch<Fmu>(`${twinPath(slug)}/fmus/${enc(name)}`, { signal });
}

export function uploadFmu(slug: string, name: string, file: Blob): Promise<Fmu> {
  return apiFetch<Fmu>(`${twinPath(slug)}/fmus/${enc(name)}`, {
    method: "PUT",
    body: file,
    contentType: "application/octet-stream",
  });
}

export async function listStreams(slug: string, signal?: AbortSignal): Promise<StreamSummary[]> {
  return (await apiFetch<{ streams: StreamSummary[] }>(`${twinPath(slug)}/streams`, { signal })).streams;
}
