import { useCallback, useMemo, useRef, useState } from "react";
import { signalUnits } from "../../api/commands";
import { useSearchParams } from "react-router-dom";
import { listStreams, type StreamInfo } from "../../api/history";
import { LiveChart } from "../../components/charts/LiveChart";
import { LiveToolbar } from "../../components/charts/LiveToolbar";
import { SignalPicker } from "../../components/charts/SignalPicker";
import { StreamStatsBar } from "../../components/charts/StreamStatsBar";
import { Empty, ErrorMessage, Loading } from "../../components/common/Status";
import { useApi } from "../../hooks/useApi";
import {
  defaultRefs,
  formatRefs,
  knownRefs,
  parseRefs,
  parseWindow,
  plottableSignals,
  windowLabel,
  type SignalRef,
} from "../../live/selection";
import { useLiveSession } from "../../live/useLiveSession";
import { useTwin } from "./context";

export function LiveTab() {
  const { slug, twin } = useTwin();
  const units = useMemo(() => signalUnits(twin.document), [twin.document]);
  const streams = useApi((signal) => listStreams(slug, signal), [slug]);
  if (streams.error) return <ErrorMessage error={streams.error} onRetry={streams.reload} />;
  if (!streams.data) return <Loading what="Loading the streams" />;
  if (streams.data.length === 0) {
    return (
      <Empty>
        No data yet: connect a device that sends samples to this twin (the edge SDK, <code>twinlink simulate</code>, or
        the device WebSocket; see docs/protocol.md), then reload this tab.
      </Empty>
    );
  }
  if (plottableSignals(streams.data).length === 0) {
    return <Empty>This twin's streams hold no numeric signals to plot (only text). The History tab can export them.</Empty>;
  }
  return <LiveView slug={slug} streams={streams.data} units={units} />;
}

/** The chosen signals and window, kept in the URL so a link reproduces the view. */
function useLiveQuery(streams: StreamInfo[]) {
  const [params, setParams] = useSearchParams();
  const refs = params.has("s") ? knownRefs(streams, parseRefs(params.get("s"))) : defaultRefs(streams);
  const windowS = parseWindow(params.get("w"));
  const update = (key: string, value: string) =>
    setParams(
      (old) => {
        const next = new URLSearchParams(old);
        next.set(key, value);
        return next;
      },
      { replace: true },
    );
  return {
    refs,
    windowS,
    setRefs: (next: SignalRef[]) => update("s", formatRefs(next)),
    setWindow: (seconds: number) => update("w", String(seconds)),
  };
}

function LiveView({ slug, streams, units }: { slug: string; streams: StreamInfo[]; units: Map<string, string> }) {
  const { refs, windowS, setRefs, setWindow } = useLiveQuery(streams);
  const [paused, setPaused] = useState(false);
  const [zoom, setZoom] = useState<[number, number] | null>(null);
  const columns = useRef<() => number>(() => 800);
  const onColumns = useCallback((get: () => number) => (columns.current = get), []);
  const session = useLiveSession({ slug, refs, windowS, paused, backfillPoints: () => 2 * columns.current() });

  if (session.state.kind === "unauthorized") {
    return (
      <ErrorMessage error={new Error(`The live connection was refused: ${session.state.reason}. Sign in again to watch live data.`)} />
    );
  }
  return (
    <div className="chart-layout">
      <SignalPicker streams={streams} selected={refs} onChange={setRefs} />
      <div className="chart-main">
        <LiveToolbar
          paused={paused}
          onPause={setPaused}
          windowS={windowS}
          onWindow={(seconds) => {
            setZoom(null);
            setWindow(seconds);
          }}
          zoomed={zoom !== null}
          onFollow={() => setZoom(null)}
          points={session.snapshot.points}
          state={session.state}
        />
        <StreamStatsBar stats={session.snapshot.stats} />
        {session.maxRate !== undefined && (
          <p className="muted">
            Live data is thinned to at most {session.maxRate.toLocaleString("en-US")} samples/s per stream so that a{" "}
            {windowLabel(windowS)} window fits in this page's memory.
          </p>
        )}
        {session.problems.map((problem) => (
          <ErrorMessage key={problem} error={new Error(problem)} />
        ))}
        {refs.length === 0 ? (
          <Empty>Choose one or more signals to plot.</Empty>
        ) : (
          <LiveChart
            store={session.store}
            windowS={windowS}
            paused={paused}
            zoom={zoom}
            onZoom={setZoom}
            onFollow={() => setZoom(null)}
            serverNow={session.serverNow}
            onColumns={onColumns}
            units={refs.map((ref) => units.get(ref.signal))}
          />
        )}
        <p className="muted">
          Each signal holds its last value until the next sample; a dashed line is a value held with no sample for much longer than
          the signal&apos;s usual step (a signal sent only when it changes, or a device gone quiet). Drag over the chart to zoom (the
          chart then stops following); double-click or “Follow live” to follow again. Paused, this page unsubscribes and receives
          nothing; Resume loads the window from history and subscribes again.
        </p>
      </div>
    </div>
  );
}
