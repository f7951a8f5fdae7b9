import { isPlottable, type StreamInfo } from "../../api/history";
import { refKey, type SignalRef } from "../../live/selection";
import { WordBreaks } from "../common/WordBreaks";

const KIND_LABEL: Record<string, string> = { integer: "int", number: "num", bool: "bool", string: "text", mixed: "mixed" };

/** Checkboxes of signals grouped by stream; text signals are listed but cannot be chosen. */
export function SignalPicker({
  streams,
  selected,
  onChange,
}: {
  streams: StreamInfo[];
  selected: SignalRef[];
  onChange: (refs: SignalRef[]) => void;
}) {
  const chosen = new Set(selected.map(refKey));
  const toggle = (ref: SignalRef, on: boolean) => {
    if (on) onChange([...selected, ref]);
    else onChange(selected.filter((r) => refKey(r) !== refKey(ref)));
  };
  return (
    <div className="signal-picker">
      {streams.map((stream) => (
        <fieldset key={stream.name}>
          <legend>{stream.name}</legend>
          {stream.signals.map((signal) => {
            const ref = { stream: stream.name, signal: signal.name };
            const plottable = isPlottable(signal.kind);
            return (
              <label key={signal.name} title={plottable ? undefined : "text signals cannot be plotted"}>
                <input
                  type="checkbox"
                  checked={chosen.has(refKey(ref))}
                  disabled={!plottable}
                  onChange={(e) => toggle(ref, e.target.checked)}
                  aria-label={`${stream.name}/${signal.name}`}
                />
                <span className="signal-name">
                  <WordBreaks text={signal.name} />
                </span>
                <span className="kind">{KIND_LABEL[signal.kind] ?? signal.kind}</span>
              </label>
            );
          })}
        </fieldset>
      ))}
    </div>
  );
}
