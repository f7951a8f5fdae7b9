import { AGGREGATE_FNS, isPlottable, type AggregateFn, type StreamInfo } from "../../api/history";
import { defaultRefs } from "../../live/selection";
import { SignalPicker } from "./SignalPicker";
import { BUCKETS, PRESETS, type RangeChoice } from "./historyData";

export type HistoryMode = "downsample" | "aggregate";

export interface HistoryQuery {
  stream: string;
  signals: string[];
  range: RangeChoice;
  mode: HistoryMode;
  /** "auto" or one of BUCKETS. */
  bucket: string;
  fn: AggregateFn;
}

const DEFAULT_SIGNALS = 3;

/** The stream and signals the Live tab would show first (the measured angle of the demo rig,
 * else the first numeric signals), over the last hour. */
export function defaultQuery(streams: StreamInfo[]): HistoryQuery {
  const first = defaultRefs(streams)[0];
  const stream = streams.find((s) => s.name === first?.stream) ?? streams[0];
  const preferred = defaultRefs(streams).filter((r) => r.stream === stream?.name).map((r) => r.signal);
  return {
    stream: stream?.name ?? "",
    signals: preferred,
    range: { preset: "1h" },
    mode: "downsample",
    bucket: "auto",
    fn: "avg",
  };
}

function plottableNames(stream: StreamInfo): string[] {
  return stream.signals.filter((g) => isPlottable(g.kind)).map((g) => g.name);
}

interface ControlsProps {
  streams: StreamInfo[];
  query: HistoryQuery;
  onChange: (query: HistoryQuery) => void;
}

export function StreamAndSignals({ streams, query, onChange }: ControlsProps) {
  const stream = streams.find((s) => s.name === query.stream);
  const pickStream = (name: string) => {
    const next = streams.find((s) => s.name === name);
    onChange({ ...query, stream: name, signals: next ? plottableNames(next).slice(0, DEFAULT_SIGNALS) : [] });
  };
  return (
    <div className="signal-picker">
      <label>
        Stream
        <select value={query.stream} onChange={(e) => pickStream(e.target.value)}>
          {streams.map((s) => (
            <option key={s.name} value={s.name}>
              {s.name}
            </option>
          ))}
        </select>
      </label>
      {stream && (
        <SignalPicker
          streams={[stream]}
          selected={query.signals.map((signal) => ({ stream: stream.name, signal }))}
          onChange={(refs) => onChange({ ...query, signals: refs.map((r) => r.signal) })}
        />
      )}
    </div>
  );
}

export function RangeControls({ query, onChange }: Omit<ControlsProps, "streams">) {
  const range = query.range;
  const custom = !("preset" in range);
  const setPreset = (value: string) =>
    onChange({ ...query, range: value === "custom" ? { from: "", to: "" } : { preset: value } });
  return (
    <div className="range-inputs">
      <label>
        Range
        <select value={"preset" in range ? range.preset : "custom"} onChange={(e) => setPreset(e.target.value)}>
          {PRESETS.map((p) => (
            <option key={p.value} value={p.value}>
              {p.label}
            </option>
          ))}
          <option value="custom">custom</option>
        </select>
      </label>
      {custom && (
        <>
          <label>
            From
            <input type="datetime-local" step={1} value={range.from} onChange={(e) => onChange({ ...query, range: { ...range, from: e.target.value } })} />
          </label>
          <label>
            To
            <input type="datetime-local" step={1} value={range.to} onChange={(e) => onChange({ ...query, range: { ...range, to: e.target.value } })} />
          </label>
        </>
      )}
    </div>
  );
}

export function ModeControls({ query, onChange, autoBucket }: Omit<ControlsProps, "streams"> & { autoBucket: string }) {
  return (
    <div className="range-inputs">
      <label>
        Mode
        <select value={query.mode} onChange={(e) => onChange({ ...query, mode: e.target.value as HistoryMode })}>
          <option value="downsample">Downsampled (min/max)</option>
          <option value="aggregate">Aggregate</option>
        </select>
      </label>
      {query.mode === "aggregate" && (
        <>
          <label>
            Bucket
            <select value={query.bucket} onChange={(e) => onChange({ ...query, bucket: e.target.value })}>
              <option value="auto">auto ({autoBucket})</option>
              {BUCKETS.map((b) => (
                <option key={b.value} value={b.value}>
                  {b.value}
                </option>
              ))}
            </select>
          </label>
          <label>
            Function
            <select value={query.fn} onChange={(e) => onChange({ ...query, fn: e.target.value as AggregateFn })}>
              {AGGREGATE_FNS.map((fn) => (
                <option key={fn} value={fn}>
                  {fn}
                </option>
              ))}
            </select>
          </label>
        </>
      )}
    </div>
  );
}
