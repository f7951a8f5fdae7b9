import { useMemo, useState } from "react";
import { signalUnits } from "../../api/commands";
import {
  aggregate,
  downloadExport,
  downsample,
  lastBefore,
  listStreams,
  type AggregateAnswer,
  type AggregateFn,
  type DownsampleAnswer,
  type ExportFormat,
  type StreamInfo,
  type TimedSample,
} from "../../api/history";
import { AggregateRows, SummaryTable } from "../../components/charts/HistoryTable";
import {
  defaultQuery,
  ModeControls,
  RangeControls,
  StreamAndSignals,
  type HistoryQuery,
} from "../../components/charts/HistoryControls";
import {
  aggregateFrame,
  autoBucket,
  downsampleFrame,
  firstTimesOfAggregate,
  firstTimesOfDownsample,
  holdsValue,
  isoToLocal,
  rangeSeconds,
  signalsWithoutStart,
  summarize,
  toTimeRange,
  type RangeChoice,
} from "../../components/charts/historyData";
import { assignScales, magnitude } from "../../components/charts/scales";
import { frameIsEmpty } from "../../components/charts/steps";
import { TimeChart } from "../../components/charts/TimeChart";
import { Empty, ErrorMessage, Loading } from "../../components/common/Status";
import { useApi } from "../../hooks/useApi";
import { useTwin } from "./context";

export function HistoryTab() {
  const { slug, twin } = useTwin();
  const units = useMemo(() => signalUnits(twin.document), [twin.document]);
  const streams = useApi((signal) => listStreams(slug, signal), [slug]);
  if (streams.error) return <ErrorMessage error={streams.error} onRetry={streams.reload} />;
  if (!streams.data) return <Loading what="Loading the streams" />;
  if (streams.data.length === 0) {
    return <Empty>No data yet: this twin has no stored samples. Connect a device (see docs/protocol.md).</Empty>;
  }
  return <HistoryView slug={slug} streams={streams.data} units={units} />;
}

/** The values before a range's start of signals sent on change: how far back to look for one
 * that changed within the range (one that did not is found however old). */
const LOOKBACK_S = 3600;

interface Before {
  /** Per signal, its last sample before the range, when it has one and it was needed. */
  before: Record<string, TimedSample>;
  /** Why the values before the range could not be read, if they could not. */
  beforeProblem?: string;
  /** When the answer came (ms): the end of an open range. */
  loadedAt: number;
}

type Loaded =
  | ({ mode: "downsample"; signals: string[]; answer: DownsampleAnswer } & Before)
  | ({ mode: "aggregate"; signals: string[]; fn: AggregateFn; answer: AggregateAnswer } & Before);

async function valuesBefore(
  slug: string,
  stream: string,
  names: string[],
  startNs: number | null | undefined,
  seconds: number,
  signal: AbortSignal,
): Promise<Before> {
  if (names.length === 0 || startNs === null || startNs === undefined) return { before: {}, loadedAt: Date.now() };
  try {
    const before = await lastBefore(slug, stream, names, startNs, Math.max(seconds, LOOKBACK_S), signal);
    return { before, loadedAt: Date.now() };
  } catch (err) {
    if (signal.aborted) throw err;
    // The samples in the range are drawn all the same; only the stretch before the first is not.
    const beforeProblem = `The values from before this range could not be read (${err instanceof Error ? err.message : String(err)}).`;
    return { before: {}, beforeProblem, loadedAt: Date.now() };
  }
}

async function load(slug: string, query: HistoryQuery, bucket: string, columns: number, signal: AbortSignal): Promise<Loaded | null> {
  if (!query.stream || query.signals.length === 0) return null;
  const range = toTimeRange(query.range);
  const seconds = rangeSeconds(query.range);
  const signals = [...query.signals];
  if (query.mode === "aggregate") {
    const answer = await aggregate(slug, query.stream, signals, range, bucket, query.fn, signal);
    const names = holdsValue(query.fn) && answer.start ? signalsWithoutStart(firstTimesOfAggregate(answer, signals, query.fn), answer.start, answer.bucket_ns) : [];
    const before = await valuesBefore(slug, query.stream, names, answer.start, seconds, signal);
    return { mode: "aggregate", signals, fn: query.fn, answer, ...before };
  }
  const answer = await downsample(slug, query.stream, signals, range, 2 * columns, signal);
  // One bucket of the min/max downsample: a first point within it is at the start, as drawn.
  const bucketNs = (seconds * 1e9) / columns;
  const names = answer.start ? signalsWithoutStart(firstTimesOfDownsample(answer, signals), answer.start, bucketNs) : [];
  const before = await valuesBefore(slug, query.stream, names, answer.start, seconds, signal);
  return { mode: "downsample", signals, answer, ...before };
}

function badRange(range: RangeChoice): string | null {
  if ("preset" in range || !range.from || !range.to) return null;
  return new Date(range.from) < new Date(range.to) ? null : "“From” must be before “To”.";
}

function HistoryView({ slug, streams, units }: { slug: string; streams: StreamInfo[]; units: Map<string, string> }) {
  const [query, setQuery] = useState<HistoryQuery>(() => defaultQuery(streams));
  // The ranges before each zoom, so a double-click goes back one step.
  const [zoomedFrom, setZoomedFrom] = useState<RangeChoice[]>([]);
  const [columns, setColumns] = useState<number | null>(null);
  const measure = (el: HTMLDivElement | null) => {
    if (el && columns === null) setColumns(el.clientWidth > 0 ? Math.min(4000, el.clientWidth) : 1000);
  };
  const bucket = query.bucket === "auto" ? autoBucket(rangeSeconds(query.range), columns ?? 1000) : query.bucket;
  const problem = badRange(query.range);
  const result = useApi(
    (signal) => (columns === null || problem ? Promise.resolve(null) : load(slug, query, bucket, columns, signal)),
    [slug, JSON.stringify(query), bucket, columns, problem],
  );
  const change = (next: HistoryQuery) => {
    setZoomedFrom([]);
    setQuery(next);
  };
  const zoom = ([a, b]: [number, number]) => {
    setZoomedFrom((stack) => [...stack, query.range]);
    setQuery({ ...query, range: { from: isoToLocal(Math.floor(a)), to: isoToLocal(Math.ceil(b)) } });
  };
  const unzoom = () => {
    const previous = zoomedFrom[zoomedFrom.length - 1];
    if (!previous) return;
    setZoomedFrom(zoomedFrom.slice(0, -1));
    setQuery({ ...query, range: previous });
  };

  return (
    <div className="chart-layout">
      <StreamAndSignals streams={streams} query={query} onChange={change} />
      <div className="chart-main" ref={measure}>
        <div className="toolbar">
          <RangeControls query={query} onChange={change} />
          <ModeControls query={query} onChange={change} autoBucket={bucket} />
          <button type="button" onClick={result.reload}>
            Reload
          </button>
        </div>
        <DownloadButtons slug={slug} query={query} />
        {problem && <ErrorMessage error={new Error(problem)} />}
        <HistoryResult loaded={result.data} loading={result.loading} error={result.error} onZoom={zoom} onUnzoom={unzoom} units={units} />
        <p className="muted">Drag over the chart to zoom into that range; double-click to go back.</p>
      </div>
    </div>
  );
}

function HistoryResult(props: {
  loaded: Loaded | null | undefined;
  loading: boolean;
  error: Error | undefined;
  onZoom: (range: [number, number]) => void;
  onUnzoom: () => void;
  units: Map<string, string>;
}) {
  const { loaded, loading, error, units } = props;
  if (error) return <ErrorMessage error={error} />;
  if (loaded === undefined) return <Loading what="Loading the history" />;
  if (loaded === null) return <Empty>Choose one or more numeric signals.</Empty>;
  const { frame, range } =
    loaded.mode === "aggregate"
      ? aggregateFrame(loaded.answer, loaded.signals, loaded.fn, loaded.before, loaded.loadedAt)
      : downsampleFrame(loaded.answer, loaded.signals, loaded.before, loaded.loadedAt);
  const labels = loaded.signals.map((s) => (loaded.mode === "aggregate" ? `${loaded.fn}(${s})` : s));
  const scales = assignScales(frame.data.slice(1).map((y) => magnitude(y)));
  // A count has no unit; the other functions keep the signal's.
  const unitOf = (signal: string) => (loaded.mode === "aggregate" && loaded.fn === "count" ? undefined : units.get(signal));
  const series = labels.map((label, i) => ({ label, scale: scales[i], unit: unitOf(loaded.signals[i] as string) }));
  return (
    <>
      {loading && <Loading what="Updating" />}
      {frameIsEmpty(frame) ? (
        <Empty>No samples of these signals in this range, nor before it.</Empty>
      ) : (
        <TimeChart series={series} label={`History of ${labels.join(", ")}`} frame={frame} xRange={range} onZoom={props.onZoom} onResetZoom={props.onUnzoom} />
      )}
      {loaded.beforeProblem && <p className="muted">{loaded.beforeProblem}</p>}
      {loaded.mode === "aggregate" ? (
        <AggregateRows answer={loaded.answer} signals={loaded.signals} fn={loaded.fn} />
      ) : (
        <SummaryTable rows={summarize(loaded.answer, loaded.signals)} />
      )}
    </>
  );
}

function DownloadButtons({ slug, query }: { slug: string; query: HistoryQuery }) {
  const [busy, setBusy] = useState<ExportFormat | null>(null);
  const [error, setError] = useState<Error>();
  const [saved, setSaved] = useState<string>();
  const download = async (format: ExportFormat) => {
    setBusy(format);
    setError(undefined);
    setSaved(undefined);
    try {
      setSaved(await downloadExport(slug, query.stream, query.signals, toTimeRange(query.range), format));
    } catch (err) {
      setError(err instanceof Error ? err : new Error(String(err)));
    } finally {
      setBusy(null);
    }
  };
  const disabled = busy !== null || !query.stream;
  return (
    <div className="toolbar">
      <button type="button" disabled={disabled} onClick={() => void download("csv")}>
        {busy === "csv" ? "Downloading…" : "Download CSV"}
      </button>
      <button type="button" disabled={disabled} onClick={() => void download("jsonl")}>
        {busy === "jsonl" ? "Downloading…" : "Download JSONL"}
      </button>
      <span className="muted">the raw samples of the chosen signals in this range</span>
      {saved && <span className="muted">Saved {saved}</span>}
      {error && <ErrorMessage error={error} />}
    </div>
  );
}
