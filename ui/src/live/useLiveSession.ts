// The Live tab's connection: one LiveClient per tab, one subscription per chosen stream (none
// while paused), the window backfilled from history with each signal's value from before it
// (a signal sent on change may have none in the window), and a snapshot of the figures for
// React a few times a second (never once per message).
import { useCallback, useEffect, useMemo, useRef, useState } from "react";
import { getToken } from "../api/client";
import { downsample, lastBefore } from "../api/history";
import type { StreamStatsSnapshot } from "./delayStats";
import { LiveClient, liveUrl, type LiveState, type WebSocketLike } from "./liveClient";
import { LiveStore, maxRateFor } from "./liveStore";
import { byStream, formatRefs, type SignalRef } from "./selection";

export const SNAPSHOT_MS = 250;
/** How far before the window to look for a signal's value when it changed within the window
 * (one that did not is answered by /latest, however old). */
const LOOKBACK_S = 3600;

export interface LiveSnapshot {
  points: number;
  stats: Map<string, StreamStatsSnapshot>;
}

export interface LiveSessionOptions {
  slug: string;
  refs: SignalRef[];
  windowS: number;
  paused: boolean;
  /** How many points per signal the history backfill asks for. */
  backfillPoints: () => number;
  createSocket?: (url: string) => WebSocketLike;
}

export interface LiveSession {
  state: LiveState;
  store: LiveStore;
  snapshot: LiveSnapshot;
  /** Refused subscriptions and failed backfills, one line each. */
  problems: string[];
  /** The server's clock now, in seconds (this browser's clock corrected by the welcome). */
  serverNow: () => number;
  maxRate: number | undefined;
}

function useLiveClient(createSocket: LiveSessionOptions["createSocket"]) {
  const [state, setState] = useState<LiveState>({ kind: "connecting" });
  const [client, setClient] = useState<LiveClient | null>(null);
  const offsetMs = useRef(0);
  useEffect(() => {
    const live = new LiveClient({
      url: liveUrl(),
      getToken,
      createSocket,
      onState: setState,
      onServerTime: (serverNs, localMs) => (offsetMs.current = serverNs / 1e6 - localMs),
    });
    live.start();
    setClient(live);
    return () => live.stop();
  }, [createSocket]);
  const serverNow = useCallback(() => (Date.now() + offsetMs.current) / 1000, []);
  return { state, client, serverNow };
}

function takeSnapshot(store: LiveStore): LiveSnapshot {
  const now = Date.now();
  const stats = new Map<string, StreamStatsSnapshot>();
  for (const [stream, s] of store.stats) stats.set(stream, s.snapshot(now));
  return { points: store.points, stats };
}

export function useLiveSession(options: LiveSessionOptions): LiveSession {
  const { slug, refs, windowS, paused } = options;
  const { state, client, serverNow } = useLiveClient(options.createSocket);
  const refsKey = formatRefs(refs);
  // eslint-disable-next-line react-hooks/exhaustive-deps
  const store = useMemo(() => new LiveStore(refs), [refsKey]);
  const [problems, setProblems] = useState<string[]>([]);
  const [snapshot, setSnapshot] = useState<LiveSnapshot>(() => takeSnapshot(store));
  const maxRate = maxRateFor(refs.length, windowS);
  const backfillPoints = useRef(options.backfillPoints);
  backfillPoints.current = options.backfillPoints;

  useEffect(() => {
    if (!client || paused || store.refs.length === 0) return;
    const report = (line: string) => setProblems((list) => (list.includes(line) ? list : [...list, line]));
    setProblems([]);
    store.clearData();
    const controller = new AbortController();
    const stops: (() => void)[] = [];
    const failed = (what: string, stream: string) => (err: unknown) => {
      if (!controller.signal.aborted) report(`${stream}: ${what} not loaded: ${err instanceof Error ? err.message : String(err)}`);
    };
    const windowStartNs = (serverNow() - windowS) * 1e9;
    for (const [stream, signals] of byStream(store.refs)) {
      stops.push(
        client.subscribe(
          { twin: slug, stream, signals, ...(maxRate ? { max_rate: maxRate } : {}) },
          {
            onSamples: (message) => store.addSamples(message),
            onDropped: (message) => store.addDropped(stream, message),
            onError: (message) => report(`${stream}: ${message}`),
          },
        ),
      );
      downsample(slug, stream, signals, { start: `-${windowS}s` }, backfillPoints.current(), controller.signal)
        .then((answer) => store.backfill(stream, answer))
        .catch(failed("history", stream));
      lastBefore(slug, stream, signals, windowStartNs, Math.max(windowS, LOOKBACK_S), controller.signal)
        .then((samples) => store.seed(stream, samples))
        .catch(failed("the values before the window", stream));
    }
    return () => {
      controller.abort();
      for (const stop of stops) stop();
    };
  }, [client, store, slug, windowS, paused, maxRate, serverNow]);

  // Paused, the figures are final at once (the subscriptions were just closed above), rather
  // than at the next refresh, which a busy browser may run late.
  useEffect(() => {
    if (paused) setSnapshot(takeSnapshot(store));
  }, [paused, store]);

  useEffect(() => {
    setSnapshot(takeSnapshot(store));
    const timer = setInterval(() => setSnapshot(takeSnapshot(store)), SNAPSHOT_MS);
    return () => clearInterval(timer);
  }, [store]);

  return { state, store, snapshot, problems, serverNow, maxRate };
}
