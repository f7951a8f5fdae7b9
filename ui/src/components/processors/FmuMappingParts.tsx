// The three parts of the FMU mapping view: inputs, outputs, parameters.
import type { FmuVariable } from "../../api/processors";
import { fmuInputs, fmuOutputs, fmuParameters, type FmuChoice, type FmuFeed } from "./buildSpec";
import { SignalPicker } from "./SignalPicker";

interface PartProps {
  choice: FmuChoice;
  onChange: (choice: FmuChoice) => void;
  error?: string;
}

function range(v: FmuVariable): string {
  if (v.min === null && v.max === null) return "";
  return `${v.min ?? "−∞"} … ${v.max ?? "∞"}`;
}

function numberOrUndefined(text: string): number | undefined {
  const value = Number(text);
  return text.trim() === "" || !Number.isFinite(value) ? undefined : value;
}

export function FmuInputsTable({ choice, onChange, signals, error }: PartProps & { signals: string[] }) {
  const inputs = fmuInputs(choice.variables ?? []);
  function feed(name: string, change: Partial<FmuFeed>) {
    const current = choice.feeds[name] ?? { signal: "" };
    onChange({ ...choice, feeds: { ...choice.feeds, [name]: { ...current, ...change } } });
  }
  return (
    <fieldset className="sf-group" data-path="inputs">
      <legend>Inputs: measured signal → FMU input</legend>
      {inputs.length === 0 ? (
        <p className="muted">This FMU has no real-valued inputs: it runs on its own, stepped at each sample's time.</p>
      ) : (
        <table className="table proc-mapping" aria-label="FMU inputs">
          <thead>
            <tr>
              <th>FMU input</th>
              <th>Measured signal</th>
              <th>Scale</th>
              <th>Offset</th>
            </tr>
          </thead>
          <tbody>
            {inputs.map((v) => {
              const f = choice.feeds[v.name] ?? { signal: "" };
              return (
                <tr key={v.name}>
                  <td>
                    <code>{v.name}</code> {v.unit && <span className="muted">[{v.unit}]</span>}
                    <div className="sf-hint">{[v.description, range(v) && `range ${range(v)}`].filter(Boolean).join("; ")}</div>
                  </td>
                  <td>
                    <SignalPicker label={`Signal for ${v.name}`} value={f.signal} signals={signals} none="not fed (keeps its start value)" onChange={(signal) => feed(v.name, { signal })} />
                  </td>
                  <td>
                    <input aria-label={`Scale for ${v.name}`} type="number" step="any" className="proc-narrow" placeholder="1" value={f.scale ?? ""} onChange={(e) => feed(v.name, { scale: numberOrUndefined(e.target.value) })} />
                  </td>
                  <td>
                    <input aria-label={`Offset for ${v.name}`} type="number" step="any" className="proc-narrow" placeholder="0" value={f.offset ?? ""} onChange={(e) => feed(v.name, { offset: numberOrUndefined(e.target.value) })} />
                  </td>
                </tr>
              );
            })}
          </tbody>
        </table>
      )}
      <div className="sf-hint">The FMU gets signal × scale + offset at each sample.</div>
      {error && <div className="sf-error">{error}</div>}
    </fieldset>
  );
}

export function FmuOutputsChoice({ choice, onChange, error }: PartProps) {
  const outputs = fmuOutputs(choice.variables ?? []);
  function toggle(name: string, on: boolean) {
    const next = on ? [...choice.outputs, name] : choice.outputs.filter((o) => o !== name);
    onChange({ ...choice, outputs: next });
  }
  return (
    <fieldset className="sf-group" data-path="params.outputs">
      <legend>Outputs written to the output stream</legend>
      <div className="sf-checks">
        {outputs.map((v) => (
          <span key={v.name} className="proc-output">
            <label className="sf-check">
              <input type="checkbox" checked={choice.outputs.includes(v.name)} onChange={(e) => toggle(v.name, e.target.checked)} />
              {v.name}
            </label>
            <span className="muted">{[v.unit, v.description].filter(Boolean).join(", ")}</span>
          </span>
        ))}
      </div>
      {outputs.length === 0 && <p className="muted">This FMU has no numeric outputs.</p>}
      {error && <div className="sf-error">{error}</div>}
    </fieldset>
  );
}

export function FmuParametersTable({ choice, onChange, error }: PartProps) {
  const parameters = fmuParameters(choice.variables ?? []);
  if (!parameters.length) return null;
  function set(name: string, text: string) {
    onChange({ ...choice, parameters: { ...choice.parameters, [name]: text } });
  }
  return (
    <details className="sf-group proc-details" open={Boolean(error)}>
      <summary>Parameters and start values ({parameters.length})</summary>
      <table className="table proc-mapping" aria-label="FMU parameters">
        <thead>
          <tr>
            <th>Parameter</th>
            <th>Value</th>
            <th>Range</th>
          </tr>
        </thead>
        <tbody>
          {parameters.map((v) => (
            <tr key={v.name}>
              <td>
                <code>{v.name}</code> {v.unit && <span className="muted">[{v.unit}]</span>}
                {v.variability === "tunable" && <span className="badge" title="can change while it runs, keeping the FMU's state">tunable</span>}
                <div className="sf-hint">{v.description}</div>
              </td>
              <td>
                <input
                  aria-label={`Value of ${v.name}`}
                  className="proc-narrow"
                  inputMode="decimal"
                  placeholder={v.start === null || v.start === undefined ? "" : String(v.start)}
                  value={choice.parameters[v.name] ?? ""}
                  onChange={(e) => set(v.name, e.target.value)}
                />
              </td>
              <td className="muted">{range(v)}</td>
            </tr>
          ))}
        </tbody>
      </table>
      <div className="sf-hint">Empty: the FMU's own start value (shown greyed).</div>
      {error && <div className="sf-error">{error}</div>}
    </details>
  );
}
