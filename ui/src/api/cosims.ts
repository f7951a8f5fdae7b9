// Co-simulations (issue 17): made from an uploaded file (a Maestro multi-model, twinlink's
// YAML form, or a folder as a zip or tar: an SSP archive or a document beside its FMUs), run
// by the server in a process of their own, their results as a chart and as Maestro's CSV.
import { apiFetch, apiRequest } from "./client";
import type { Schemas } from "./types";

export type CosimState = "created" | "running" | "finished" | "stopped" | "failed";
export type CosimMode = "batch" | "realtime";

/** An instance: `kind` is co-simulation, model-exchange or python. */
export type CosimInstance = Schemas["CosimInstance"];
/** A connection; each port "instance.variable", where an instance's name may hold dots itself
 * ("msd1.m1" in Maestro). */
export type CosimConnection = Schemas["CosimConnection"];
export type CosimAlgorithm = Schemas["CosimAlgorithm"];
/** The system as read from the file; `loops` the algebraic loops, each as its ports in order
 * from an output (the last feeds the first). */
export type CosimSystem = Schemas["CosimSystem"];

/** A co-simulation, its state as the app reads it (the API leaves it a string). */
export type Cosim = Omit<Schemas["Cosim"], "state"> & { state: CosimState };

/** The results column-major as uPlot takes them: `data[0]` the time, then one array per column
 * after "time" in `columns`. */
export type CosimResults = Schemas["CosimResults"];

export interface CosimRequest {
  file: File;
  name: string;
  twin?: string;
  prefix?: string;
  /** The twin's stream the signals go to (the server's default: cosim). */
  stream?: string;
  mode: CosimMode;
  factor: number;
}

const enc = encodeURIComponent;
const BASE = "/api/v1/cosims";

/** The Content-Type the server reads a file by, from its name; null for one it does not take. */
export function contentTypeOf(filename: string): string | null {
  const name = filename.toLowerCase();
  if (name.endsWith(".json")) return "application/json";
  if (name.endsWith(".yaml") || name.endsWith(".yml")) return "application/yaml";
  if (name.endsWith(".zip") || name.endsWith(".ssp")) return "application/zip";
  if (name.endsWith(".tar.gz") || name.endsWith(".tgz")) return "application/gzip";
  if (name.endsWith(".tar")) return "application/x-tar";
  return null;
}

/** A co-simulation's name from its file's: "Multi-models/msd mm.json" -> "msd-mm". */
export function nameFromFile(filename: string): string {
  const stem = filename.replace(/^.*[\\/]/, "").replace(/\.(tar\.gz|tgz|zip|ssp|tar|json|ya?ml)$/i, "");
  return stem.toLowerCase().replace(/[^a-z0-9._-]+/g, "-").replace(/^[^a-z0-9]+|-+$/g, "").slice(0, 100);
}

export async function listCosims(signal?: AbortSignal): Promise<Cosim[]> {
  const answer = await apiFetch<{ cosims: Cosim[] }>(BASE, { signal });
  return answer.cosims;
}

export function getCosim(id: string, signal?: AbortSignal): Promise<Cosim> {
  return apiFetch<Cosim>(`${BASE}/${enc(id)}`, { signal });
}

/** Create one from a file: the File is the request's body, so the browser streams it from disk. */
export function createCosim(request: CosimRequest, signal?: AbortSignal): Promise<Cosim> {
  const contentType = contentTypeOf(request.file.name) ?? "application/octet-stream";
  return apiFetch<Cosim>(BASE, {
    method: "POST",
    query: {
      name: request.name,
      twin: request.twin,
      prefix: request.twin ? request.prefix : undefined,
      stream: request.twin ? request.stream : undefined,
      mode: request.mode,
      factor: request.mode === "realtime" ? request.factor : undefined,
    },
    body: request.file,
    contentType,
    signal,
  });
}

/** Start (or start again: new results); without options it runs as it was created. */
export function startCosim(id: string, options?: { mode: CosimMode; factor: number }): Promise<Cosim> {
  return apiFetch<Cosim>(`${BASE}/${enc(id)}/start`, { method: "POST", json: options });
}

export function stopCosim(id: string): Promise<Cosim> {
  return apiFetch<Cosim>(`${BASE}/${enc(id)}/stop`, { method: "POST" });
}

export function deleteCosim(id: string): Promise<void> {
  return apiFetch<void>(`${BASE}/${enc(id)}`, { method: "DELETE" });
}

export function getResults(id: string, maxPoints = 2000, signal?: AbortSignal): Promise<CosimResults> {
  return apiFetch<CosimResults>(`${BASE}/${enc(id)}/results`, { query: { max_points: maxPoints }, signal });
}

/** Download Maestro's outputs.csv: fetched with the token (a plain link would carry none),
 * then saved from a blob URL. */
export async function downloadCsv(id: string, name: string): Promise<void> {
  const response = await apiRequest(`${BASE}/${enc(id)}/results.csv`, { accept: "text/csv" });
  const blob = await response.blob();
  const url = URL.createObjectURL(blob);
  try {
    const link = document.createElement("a");
    link.href = url;
    link.download = `${name || "cosim"}-outputs.csv`;
    document.body.appendChild(link);
    link.click();
    link.remove();
  } finally {
    // the click has handed the blob to the download; revoke after the current task
    setTimeout(() => URL.revokeObjectURL(url), 0);
  }
}

/** Whether a co-simulation may still change by itself. */
export function isRunning(cosim: Pick<Cosim, "state">): boolean {
  return cosim.state === "running";
}
