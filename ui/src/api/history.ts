// The history API of a twin's streams (docs/api.md, "History"). Times are ns since the epoch.
import { apiFetch, apiRequest } from "./client";
import type { Schemas } from "./types";

const enc = encodeURIComponent;

export type SignalKind = "integer" | "number" | "bool" | "string" | "mixed";

export type SignalInfo = Pick<Schemas["SignalInfo"], "name" | "kind" | "count" | "first" | "last">;

export type StreamInfo = Pick<Schemas["StreamInfo"], "name" | "count" | "first" | "last"> & {
  signals: SignalInfo[];
};

/** Kinds that can be drawn as a line (bools as 0 and 1). */
export function isPlottable(kind: SignalKind): boolean {
  return kind === "integer" || kind === "number" || kind === "bool";
}

/** A time range as the API takes it: ISO, integer ns, `now` or back from now (`-15m`). */
export interface TimeRange {
  start?: string;
  end?: string;
}

export type DownsampleAnswer = Pick<
  Schemas["DownsampleAnswer"],
  "stream" | "start" | "end" | "points" | "skipped" | "signals"
>;

export type AggregateFn = "avg" | "min" | "max" | "count" | "first" | "last" | "sum";
export const AGGREGATE_FNS: AggregateFn[] = ["avg", "min", "max", "count", "first", "last", "sum"];

export interface AggregateAnswer {
  stream: string;
  start?: number | null;
  end?: number | null;
  bucket: string;
  bucket_ns: number;
  fn: AggregateFn[];
  skipped: string[];
  rows: { time: number; values: Record<string, Partial<Record<AggregateFn, number | null>>> }[];
}

export type ExportFormat = "csv" | "jsonl";

/** A sample as a number (bools as 0 and 1), its time in ns. */
export interface TimedSample {
  time: number;
  value: number;
}

interface LatestAnswer {
  values: Record<string, { time: number; value: unknown }>;
}

function streamPath(slug: string, stream: string, what: string): string {
  return `/api/v1/twins/${enc(slug)}/streams/${enc(stream)}/${what}`;
}

export async function listStreams(slug: string, signal?: AbortSignal): Promise<StreamInfo[]> {
  const answer = await apiFetch<{ streams: StreamInfo[] }>(`/api/v1/twins/${enc(slug)}/streams`, { signal });
  return answer.streams;
}

export function downsampleQuery(signals: string[], range: TimeRange, points: number) {
  return { points: Math.max(2, Math.round(points)), start: range.start, end: range.end, signals: signals.join(",") };
}

export function downsample(
  slug: string,
  stream: string,
  signals: string[],
  range: TimeRange,
  points: number,
  signal?: AbortSignal,
): Promise<DownsampleAnswer> {
  return apiFetch<DownsampleAnswer>(streamPath(slug, stream, "downsample"), {
    query: downsampleQuery(signals, range, points),
    signal,
  });
}

export function aggregateQuery(signals: string[], range: TimeRange, bucket: string, fn: AggregateFn) {
  return { bucket, fn, start: range.start, end: range.end, signals: signals.join(",") };
}

export function aggregate(
  slug: string,
  stream: string,
  signals: string[],
  range: TimeRange,
  bucket: string,
  fn: AggregateFn,
  signal?: AbortSignal,
): Promise<AggregateAnswer> {
  return apiFetch<AggregateAnswer>(streamPath(slug, stream, "aggregate"), {
    query: aggregateQuery(signals, range, bucket, fn),
    signal,
  });
}

function plotted(value: unknown): number | null {
  if (typeof value === "number") return value;
  if (typeof value === "boolean") return value ? 1 : 0;
  return null;
}

/** Per signal, its last sample before `startNs` (the value a signal sent on change holds at a
 * range's start), for the signals that have one. Two cheap reads: `/latest` answers every
 * signal that sent nothing since; for the others, the `last` aggregate over `lookbackS` before
 * the start, whose time is then its bucket's start (a lower bound). The API has no "newest
 * sample before a time"; with one, this would be a single exact read. */
export async function lastBefore(
  slug: string,
  stream: string,
  signals: string[],
  startNs: number,
  lookbackS: number,
  signal?: AbortSignal,
): Promise<Record<string, TimedSample>> {
  const found: Record<string, TimedSample> = {};
  if (signals.length === 0) return found;
  const latest = await apiFetch<LatestAnswer>(streamPath(slug, stream, "latest"), { query: { signals: signals.join(",") }, signal });
  const since: string[] = [];
  for (const name of signals) {
    const sample = latest.values[name];
    if (!sample) continue; // never sent
    const value = plotted(sample.value);
    if (sample.time >= startNs) since.push(name);
    else if (value !== null) found[name] = { time: sample.time, value };
  }
  if (since.length === 0) return found;
  // ns near 2^60 are floats in JavaScript (256 ns apart): end a microsecond before the start.
  const end = Math.round(startNs) - 1000;
  const lookback = Math.max(1, Math.round(lookbackS));
  const range = { start: String(end - lookback * 1e9), end: String(end) };
  const answer = await aggregate(slug, stream, since, range, `${lookback}s`, "last", signal);
  for (const row of answer.rows) {
    for (const name of since) {
      const value = row.values[name]?.last;
      if (typeof value === "number") found[name] = { time: row.time, value };
    }
  }
  return found;
}

function exportQuery(signals: string[], range: TimeRange, format: ExportFormat) {
  return { format, start: range.start, end: range.end, signals: signals.join(",") };
}

/** The file name of a Content-Disposition header, if it names one. */
export function fileNameFrom(disposition: string | null): string | null {
  if (!disposition) return null;
  const star = /filename\*\s*=\s*(?:UTF-8'')?([^;]+)/i.exec(disposition);
  if (star?.[1]) return decodeURIComponent(star[1].trim().replace(/^"|"$/g, ""));
  const plain = /filename\s*=\s*("([^"]*)"|[^;]+)/i.exec(disposition);
  const name = plain?.[2] ?? plain?.[1];
  return name ? name.trim() : null;
}

/** Fetch an export with the token (a plain link could not send it) and hand it to the
 * browser as a download; answers the file name used. */
export async function downloadExport(
  slug: string,
  stream: string,
  signals: string[],
  range: TimeRange,
  format: ExportFormat,
): Promise<string> {
  const response = await apiRequest(streamPath(slug, stream, "export"), {
    query: exportQuery(signals, range, format),
    accept: format === "csv" ? "text/csv" : "application/x-ndjson",
  });
  const blob = await response.blob();
  const name = fileNameFrom(response.headers.get("Content-Disposition")) ?? `${slug}-${stream}.${format}`;
  saveBlob(blob, name);
  return name;
}

/** Hand a blob to the browser as a download named `name`. */
export function saveBlob(blob: Blob, name: string): void {
  const url = URL.createObjectURL(blob);
  const link = document.createElement("a");
  link.href = url;
  link.download = name;
  link.style.display = "none";
  document.body.appendChild(link);
  link.click();
  link.remove();
  // The click starts the download synchronously; revoke later so slow browsers still read it.
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}
