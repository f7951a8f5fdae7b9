// One co-simulation: its state and progress, Start / Stop / Delete, what it is made of (the
// instances and the connection graph), and its results as a chart (read again while it runs)
// and as Maestro's CSV.
import { useEffect, useState } from "react";
import { Link, useLocation, useNavigate, useParams } from "react-router-dom";
import {
  deleteCosim,
  downloadCsv,
  getCosim,
  getResults,
  isRunning,
  startCosim,
  stopCosim,
  type Cosim,
  type CosimMode,
} from "../api/cosims";
import { Empty, ErrorMessage, Loading } from "../components/common/Status";
import { ConnectionGraph } from "../components/cosims/ConnectionGraph";
import { formatSeconds, formatWhen, Progress, StateBadge } from "../components/cosims/CosimBits";
import { ResultsChart } from "../components/cosims/ResultsChart";
import { useApi } from "../hooks/useApi";
import type { CreatedState } from "./CosimsPage";
import "../components/processors/processors.css";
import "../components/deployments/deployments.css";
import "../components/cosims/cosims.css";

/** How often a running co-simulation's state and its results are read again. */
export const RUNNING_REFRESH_MS = 1000;
export const RESULTS_REFRESH_MS = 2000;
/** Points per column asked of the server (about two per pixel column of a wide chart). */
export const MAX_POINTS = 2000;

interface ActionsProps {
  cosim: Cosim;
  onChanged: () => void;
  onDeleted: () => void;
}

function Actions({ cosim, onChanged, onDeleted }: ActionsProps) {
  const id = String(cosim.id);
  const [mode, setMode] = useState<CosimMode>(cosim.mode === "realtime" ? "realtime" : "batch");
  const [factor, setFactor] = useState(String(cosim.factor ?? 1));
  const [busy, setBusy] = useState(false);
  const [error, setError] = useState<Error | null>(null);
  const running = isRunning(cosim);

  async function act(fn: () => Promise<unknown>, after: () => void = onChanged) {
    setBusy(true);
    setError(null);
    try {
      await fn();
      after();
    } catch (err) {
      setError(err instanceof Error ? err : new Error(String(err)));
    } finally {
      setBusy(false);
    }
  }

  function start() {
    const speed = Number(factor);
    if (mode === "realtime" && !(Number.isFinite(speed) && speed > 0)) {
      setError(new Error("The speed factor is a number above 0: 1 is the wall clock, 2 twice as fast."));
      return;
    }
    void act(() => startCosim(id, { mode, factor: mode === "realtime" ? speed : 1 }));
  }

  function remove() {
    if (!window.confirm(`Delete ${cosim.name} and its results?`)) return;
    void act(() => deleteCosim(id), onDeleted);
  }

  const hasResults = cosim.state !== "created" && !running;
  return (
    <div className="cosim-actions" aria-label="Actions">
      {running ? (
        <button type="button" disabled={busy} onClick={() => void act(() => stopCosim(id))}>
          Stop
        </button>
      ) : (
        <>
          <label htmlFor="cosim-mode">Mode</label>
          <select id="cosim-mode" value={mode} onChange={(e) => setMode(e.target.value as CosimMode)}>
            <option value="batch">batch</option>
            <option value="realtime">real time</option>
          </select>
          {mode === "realtime" && (
            <>
              <label htmlFor="cosim-factor">Speed factor</label>
              <input id="cosim-factor" type="number" min="0" step="any" value={factor} onChange={(e) => setFactor(e.target.value)} />
            </>
          )}
          <button type="button" disabled={busy} onClick={start}>
            {cosim.state === "created" ? "Start" : "Start again"}
          </button>
        </>
      )}
      <button
        type="button"
        disabled={busy || !hasResults}
        onClick={() => void act(() => downloadCsv(id, cosim.name), () => undefined)}
        title={hasResults ? "Maestro's outputs.csv" : "There are results once a run has ended"}
      >
        Download CSV
      </button>
      {!running && (
        <button type="button" className="proc-danger" disabled={busy} onClick={remove}>
          Delete
        </button>
      )}
      {error && <ErrorMessage error={error} />}
    </div>
  );
}

function Facts({ cosim }: { cosim: Cosim }) {
  const s = cosim.system;
  const a = s.algorithm;
  const step = a.kind === "var-step" ? `variable, from ${formatSeconds(a.size)} (${a.min_size ?? "?"} to ${a.max_size ?? "?"} s)` : `fixed, ${formatSeconds(a.size)}`;
  return (
    <dl className="props">
      <dt>Read from</dt>
      <dd>{s.source || "?"}</dd>
      <dt>Master</dt>
      <dd>
        {a.master}, step {step}
      </dd>
      <dt>Time</dt>
      <dd>
        {formatSeconds(s.start_time)} to {s.end_time != null ? formatSeconds(s.end_time) : "open end"}
      </dd>
      <dt>Mode</dt>
      <dd>{cosim.mode === "realtime" ? `real time, speed ×${cosim.factor}` : "batch, as fast as it goes"}</dd>
      <dt>Twin</dt>
      <dd>
        {cosim.twin ? (
          <>
            <Link to={`/twins/${encodeURIComponent(cosim.twin)}/history`}>{cosim.twin}</Link>, stream <span className="mono">{cosim.stream || "cosim"}</span>, signals{" "}
            <span className="mono">{cosim.prefix ?? ""}instance.variable</span>
          </>
        ) : (
          "none"
        )}
      </dd>
      <dt>Owner</dt>
      <dd>{cosim.owner}</dd>
      <dt>Created</dt>
      <dd>{formatWhen(cosim.created_at)}</dd>
      {cosim.started_at != null && (
        <>
          <dt>Started</dt>
          <dd>{formatWhen(cosim.started_at)}</dd>
        </>
      )}
      {cosim.ended_at != null && (
        <>
          <dt>Ended</dt>
          <dd>{formatWhen(cosim.ended_at)}</dd>
        </>
      )}
      {cosim.rows != null && (
        <>
          <dt>Rows</dt>
          <dd>{cosim.rows}</dd>
        </>
      )}
    </dl>
  );
}

function Instances({ cosim }: { cosim: Cosim }) {
  return (
    <div className="table-scroll">
      <table className="table" aria-label="Instances">
        <thead>
          <tr>
            <th>Instance</th>
            <th>FMU</th>
            <th>Kind</th>
            <th>Process</th>
          </tr>
        </thead>
        <tbody>
          {cosim.system.instances.map((i) => (
            <tr key={i.name}>
              <td className="mono">{i.name}</td>
              <td className="mono">{i.fmu}</td>
              <td>{i.kind}</td>
              <td>{i.isolated || i.kind === "python" ? "its own" : "the run's"}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}

/** The results chart: read when the state changes, and again and again while it runs. */
function Results({ cosim }: { cosim: Cosim }) {
  const id = String(cosim.id);
  const running = isRunning(cosim);
  const results = useApi((signal) => (cosim.state === "created" ? Promise.resolve(null) : getResults(id, MAX_POINTS, signal)), [id, cosim.state, cosim.started_at]);
  const { reload } = results;
  useEffect(() => {
    if (!running) return;
    const timer = window.setInterval(reload, RESULTS_REFRESH_MS);
    return () => window.clearInterval(timer);
  }, [running, reload]);
  if (results.error) return <ErrorMessage error={results.error} onRetry={reload} />;
  if (results.data === undefined) return <Loading />;
  const data = results.data;
  if (!data || data.columns.length < 2 || (data.data[0]?.length ?? 0) === 0) {
    return <Empty>{cosim.state === "created" ? "No results yet: choose “Start”." : running ? "No rows yet: the first come in a moment." : "This run wrote no rows."}</Empty>;
  }
  return <ResultsChart results={data} />;
}

/** Why the page that made it could not start it: shown once, taken out of the history entry so
 * that a reload does not show it again. */
function useStartError(): string | undefined {
  const location = useLocation();
  const navigate = useNavigate();
  const [error] = useState(() => (location.state as CreatedState | null)?.startError);
  useEffect(() => {
    if (location.state) navigate(location.pathname, { replace: true, state: null });
  }, [location.state, location.pathname, navigate]);
  return error;
}

export function CosimPage() {
  const { id = "" } = useParams();
  const navigate = useNavigate();
  const startError = useStartError();
  const cosim = useApi((signal) => getCosim(id, signal), [id]);
  const { reload } = cosim;
  const running = cosim.data ? isRunning(cosim.data) : false;
  useEffect(() => {
    if (!running) return;
    const timer = window.setInterval(reload, RUNNING_REFRESH_MS);
    return () => window.clearInterval(timer);
  }, [running, reload]);

  if (cosim.error && !cosim.data) return <main className="page"><ErrorMessage error={cosim.error} onRetry={reload} /></main>;
  if (!cosim.data) return <main className="page"><Loading /></main>;
  const c = cosim.data;
  return (
    <main className="page">
      <p>
        <Link to="/cosims">Co-simulations</Link> /
      </p>
      <h1>
        {c.name} <StateBadge state={c.state} />
      </h1>
      {cosim.error && <ErrorMessage error={cosim.error} />}
      {startError && c.state === "created" && <ErrorMessage error={new Error(`Made, but not started: ${startError}`)} />}
      <Progress cosim={c} wide />
      {c.message && (
        <p className={c.state === "failed" ? "proc-error-text" : "muted"} role={c.state === "failed" ? "alert" : "status"}>
          {c.message}
        </p>
      )}
      <Actions key={`${c.mode}:${c.factor}`} cosim={c} onChanged={reload} onDeleted={() => navigate("/cosims")} />
      <h2>Results</h2>
      <Results cosim={c} />
      <h2>Connections</h2>
      <ConnectionGraph system={c.system} />
      <h2>Instances</h2>
      <Instances cosim={c} />
      <h2>Settings</h2>
      <Facts cosim={c} />
    </main>
  );
}
