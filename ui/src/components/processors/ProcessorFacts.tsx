// What a processor is set to, how it is doing, and what its running blueprint reads and writes.
import type { ReactNode } from "react";
import type { FmuVariable, InputMap, Processor } from "../../api/processors";
import { formatClock } from "../common/time";
import { FmuVariables } from "./FmuVariables";
import { formatCount, formatMb, formatMicros, formatMillis, formatNs } from "./format";
import { StateBadge } from "./StateBadge";

function inputText(value: InputMap | string): string {
  if (typeof value === "string") return value;
  const { scale = 1, offset = 0 } = value; // the server's defaults
  const parts = [value.signal];
  if (scale !== 1) parts.push(`× ${scale}`);
  if (offset !== 0) parts.push(`${offset < 0 ? "−" : "+"} ${Math.abs(offset)}`);
  return parts.join(" ");
}

function Row({ term, children }: { term: string; children: ReactNode }) {
  return (
    <div className="prop-row">
      <dt>{term}</dt>
      <dd>{children}</dd>
    </div>
  );
}

export function ProcessorConfig({ processor: p }: { processor: Processor }) {
  const inputs = Object.entries(p.inputs ?? {});
  return (
    <dl className="props" aria-label="Configuration">
      <Row term="Blueprint">
        <code>{p.blueprint}</code>
      </Row>
      <Row term="Reads">
        <code>{p.source}</code>
      </Row>
      <Row term="Writes">
        <code>{p.output || p.name}</code>
      </Row>
      <Row term="Inputs">
        {inputs.length ? (
          <ul className="proc-plain">
            {inputs.map(([name, value]) => (
              <li key={name}>
                <code>{name}</code> ← <code>{inputText(value)}</code>
              </li>
            ))}
          </ul>
        ) : (
          <span className="muted">same names as the source signals</span>
        )}
      </Row>
      <Row term="Parameters">
        <pre className="proc-json">{JSON.stringify(p.params ?? {}, null, 2)}</pre>
      </Row>
      <Row term="Rates">
        <span className="mono">
          input ≥ {p.rates?.min_input_spacing_s ?? 0} s, step ≥ {p.rates?.min_step_spacing_s ?? 0} s, output ≥{" "}
          {p.rates?.min_output_spacing_s ?? 0} s, batch ≤ {formatCount(p.rates?.max_batch)}
        </span>
      </Row>
      <Row term="Limits">
        {formatCount(p.memory_limit_mb)} MB memory, {p.batch_timeout_s} s per batch
      </Row>
      <Row term="Enabled">{p.enabled ? "yes" : "no"}</Row>
      <Row term="Changed">{formatNs(p.modified_ns)}</Row>
    </dl>
  );
}

export function ProcessorStatus({ processor: p }: { processor: Processor }) {
  const s = p.stats;
  return (
    <dl className="props" aria-label="Status">
      <Row term="State">
        <StateBadge state={p.state} />
        {p.state === "backoff" && p.restart_at && <span className="muted"> restart at {formatClock(p.restart_at * 1000)}</span>}
      </Row>
      <Row term="Process id">{p.pid ?? <span className="muted">none</span>}</Row>
      <Row term="Last error">{p.last_error ? <span className="proc-error-text">{p.last_error}</span> : <span className="muted">none</span>}</Row>
      <Row term="Samples in / out">
        {formatCount(s?.samples_in)} / {formatCount(s?.samples_out)}
      </Row>
      <Row term="Dropped">{formatCount(s?.dropped)}</Row>
      <Row term="Batches">{formatCount(s?.batches)}</Row>
      <Row term="Restarts / crashes">
        {formatCount(s?.restarts)} / {formatCount(s?.crashes)}
      </Row>
      <Row term="Memory (RSS)">{formatMb(s?.rss_bytes)}</Row>
      <Row term="Step time p50 / p99">
        {formatMicros(s?.step_time_s.p50)} / {formatMicros(s?.step_time_s.p99)}
      </Row>
      <Row term="Added latency p50 / p99">
        {formatMillis(s?.added_latency_s.p50)} / {formatMillis(s?.added_latency_s.p99)}
      </Row>
    </dl>
  );
}

function Names({ names }: { names: string[] | undefined }) {
  if (!names?.length) return <span className="muted">none</span>;
  return (
    <>
      {names.map((n) => (
        <span key={n} className="chip mono">
          {n}
        </span>
      ))}
    </>
  );
}

/** What the running worker reported: its inputs, outputs and the blueprint's own description. */
export function ProcessorRunning({ processor: p }: { processor: Processor }) {
  const describe = p.running?.describe ?? {};
  const variables = Array.isArray(describe.variables) ? (describe.variables as FmuVariable[]) : null;
  const rest = Object.fromEntries(Object.entries(describe).filter(([k]) => k !== "variables"));
  if (!p.running?.inputs && !p.running?.outputs) {
    return <p className="muted">Not running: what it reads and writes is shown once its worker has started.</p>;
  }
  return (
    <div className="proc-running">
      <p>
        Reads <Names names={p.running.inputs} />
      </p>
      <p>
        Writes <Names names={p.running.outputs} />
      </p>
      {Object.keys(rest).length > 0 && (
        <details>
          <summary>What the blueprint says about itself</summary>
          <pre className="proc-json">{JSON.stringify(rest, null, 2)}</pre>
        </details>
      )}
      {variables && (
        <details>
          <summary>FMU variables ({variables.length})</summary>
          <FmuVariables variables={variables} />
        </details>
      )}
    </div>
  );
}
