// Which signals a chart shows, kept in the URL (?s=stream:signal,...&w=30) so a link
// reproduces the view.
import { isPlottable, type StreamInfo } from "../api/history";

export interface SignalRef {
  stream: string;
  signal: string;
}

export const WINDOWS_S = [10, 30, 60, 300, 900];
export const DEFAULT_WINDOW_S = 30;

/** The measured and the FMU-simulated angle of the demo rig, drawn together by default. */
const PREFERRED: SignalRef[] = [
  { stream: "telemetry", signal: "Cantilever_Angle_radians" },
  { stream: "fmu", signal: "theta" },
];
const DEFAULT_COUNT = 3;

export function refKey(ref: SignalRef): string {
  return `${ref.stream}:${ref.signal}`;
}

/** Stream names never hold a colon, signal names may: split at the first one. */
export function parseRefs(value: string | null): SignalRef[] {
  if (!value) return [];
  const refs: SignalRef[] = [];
  for (const part of value.split(",")) {
    const at = part.indexOf(":");
    if (at <= 0 || at === part.length - 1) continue;
    const ref = { stream: part.slice(0, at), signal: part.slice(at + 1) };
    if (!refs.some((r) => refKey(r) === refKey(ref))) refs.push(ref);
  }
  return refs;
}

export function formatRefs(refs: SignalRef[]): string {
  return refs.map(refKey).join(",");
}

export function parseWindow(value: string | null): number {
  const seconds = Number(value);
  return WINDOWS_S.includes(seconds) ? seconds : DEFAULT_WINDOW_S;
}

export function windowLabel(seconds: number): string {
  return seconds < 60 ? `${seconds} s` : `${seconds / 60} min`;
}

/** The numeric signals, stream by stream (streams without any are left out). */
export function plottableSignals(streams: StreamInfo[]): { stream: string; signals: string[] }[] {
  return streams
    .map((s) => ({ stream: s.name, signals: s.signals.filter((g) => isPlottable(g.kind)).map((g) => g.name) }))
    .filter((s) => s.signals.length > 0);
}

function exists(streams: StreamInfo[], ref: SignalRef): boolean {
  return plottableSignals(streams).some((s) => s.stream === ref.stream && s.signals.includes(ref.signal));
}

/** The demo's two angles when the twin has them, else the first few numeric signals of the
 * first stream that has any. */
export function defaultRefs(streams: StreamInfo[]): SignalRef[] {
  const preferred = PREFERRED.filter((ref) => exists(streams, ref));
  if (preferred.length > 0) return preferred;
  const first = plottableSignals(streams)[0];
  if (!first) return [];
  return first.signals.slice(0, DEFAULT_COUNT).map((signal) => ({ stream: first.stream, signal }));
}

/** The chosen refs that the twin has (a link may name signals that are gone). */
export function knownRefs(streams: StreamInfo[], refs: SignalRef[]): SignalRef[] {
  return refs.filter((ref) => exists(streams, ref));
}

/** The refs grouped by stream, in the order the streams first appear. */
export function byStream(refs: SignalRef[]): Map<string, string[]> {
  const groups = new Map<string, string[]>();
  for (const ref of refs) groups.set(ref.stream, [...(groups.get(ref.stream) ?? []), ref.signal]);
  return groups;
}
