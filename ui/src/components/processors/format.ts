// How the figures of processors are shown.
import { formatEpochMs } from "../common/time";

/** A time in nanoseconds since the epoch, as local date and time. */
export function formatNs(ns: number | null | undefined): string {
  if (!ns) return "—";
  return formatEpochMs(Math.floor(ns / 1e6));
}

/** Seconds as microseconds ("12.3 µs"), for step times. */
export function formatMicros(seconds: number | null | undefined): string {
  return seconds === null || seconds === undefined ? "—" : `${(seconds * 1e6).toFixed(1)} µs`;
}

/** Seconds as milliseconds ("1.23 ms"), for added latency. */
export function formatMillis(seconds: number | null | undefined): string {
  return seconds === null || seconds === undefined ? "—" : `${(seconds * 1e3).toFixed(2)} ms`;
}

/** Bytes as mebibytes ("45.2 MB"), for the worker's resident memory. */
export function formatMb(bytes: number | null | undefined): string {
  return bytes ? `${(bytes / 2 ** 20).toFixed(1)} MB` : "—";
}

export function formatCount(n: number | null | undefined): string {
  return n === null || n === undefined ? "—" : n.toLocaleString("en-US");
}

/** A docstring without the indentation of its later lines. */
export function dedent(text: string): string {
  const lines = text.split("\n");
  const indents = lines
    .slice(1)
    .filter((l) => l.trim())
    .map((l) => l.length - l.trimStart().length);
  const cut = indents.length ? Math.min(...indents) : 0;
  return [lines[0] ?? "", ...lines.slice(1).map((l) => l.slice(cut))].join("\n").trim();
}
