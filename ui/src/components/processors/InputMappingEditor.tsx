// The processor's `inputs` for any blueprint: blueprint input <- source signal * scale + offset.
import type { InputRow } from "./buildSpec";
import { SignalPicker } from "./SignalPicker";

interface Props {
  rows: InputRow[];
  onChange: (rows: InputRow[]) => void;
  signals: string[];
  error?: string;
}

function num(text: string): number | undefined {
  const value = Number(text);
  return text.trim() === "" || !Number.isFinite(value) ? undefined : value;
}

export function InputMappingEditor({ rows, onChange, signals, error }: Props) {
  function set(i: number, change: Partial<InputRow>) {
    onChange(rows.map((row, j) => (j === i ? { ...row, ...change } : row)));
  }
  return (
    <fieldset className="sf-group" data-path="inputs">
      <legend>Input mapping</legend>
      <div className="sf-hint">
        A blueprint input reads the source signal of the same name unless it is mapped here; the value used is signal × scale + offset.
      </div>
      {rows.length > 0 && (
        <table className="table proc-mapping" aria-label="Input mapping">
          <thead>
            <tr>
              <th>Blueprint input</th>
              <th>Source signal</th>
              <th>Scale</th>
              <th>Offset</th>
              <th />
            </tr>
          </thead>
          <tbody>
            {rows.map((row, i) => (
              <tr key={i}>
                <td>
                  <input aria-label={`Blueprint input ${i + 1}`} className="mono" value={row.input} placeholder="input name" onChange={(e) => set(i, { input: e.target.value })} />
                </td>
                <td>
                  <SignalPicker label={`Source signal ${i + 1}`} value={row.signal} signals={signals} none="Choose…" onChange={(signal) => set(i, { signal })} />
                </td>
                <td>
                  <input aria-label={`Scale ${i + 1}`} type="number" step="any" className="proc-narrow" placeholder="1" value={row.scale ?? ""} onChange={(e) => set(i, { scale: num(e.target.value) })} />
                </td>
                <td>
                  <input aria-label={`Offset ${i + 1}`} type="number" step="any" className="proc-narrow" placeholder="0" value={row.offset ?? ""} onChange={(e) => set(i, { offset: num(e.target.value) })} />
                </td>
                <td>
                  <button type="button" className="link-button" aria-label={`Remove input mapping ${i + 1}`} onClick={() => onChange(rows.filter((_, j) => j !== i))}>
                    Remove
                  </button>
                </td>
              </tr>
            ))}
          </tbody>
        </table>
      )}
      <button type="button" onClick={() => onChange([...rows, { input: "", signal: "" }])}>
        Add input mapping
      </button>
      {error && <div className="sf-error">{error}</div>}
    </fieldset>
  );
}
