// One deployment: its state and resources, the lifecycle buttons, every run and a run's log.
import { useEffect, useState } from "react";
import { Link, useLocation, useNavigate, useParams } from "react-router-dom";
import {
  cancelRun,
  getDeployment,
  isActive,
  listRuns,
  PHASES,
  startRun,
  transition,
  type Deployment,
  type Run,
  type Transition,
} from "../api/deployments";
import { Empty, ErrorMessage, Loading } from "../components/common/Status";
import { Reconfigure } from "../components/deployments/Reconfigure";
import { RunHistory } from "../components/deployments/RunHistory";
import { RunLog } from "../components/deployments/RunLog";
import { useApi, type ApiState } from "../hooks/useApi";
import type { CreatedState } from "./DeploymentsPage";
import "../components/processors/processors.css";
import "../components/deployments/deployments.css";

/** How often the page asks again for the state and the runs. */
export const REFRESH_MS = 3000;

/** The transitions a state allows, in the order the buttons show them. */
export function transitionsOf(state: Deployment["state"]): Transition[] {
  switch (state) {
    case "planned":
      return ["create", "terminate"];
    case "created":
    case "stopped":
      return ["start", "terminate"];
    case "running":
      return ["stop", "terminate"];
    default:
      return [];
  }
}

const LABELS: Record<Transition, string> = { create: "Create", start: "Start", stop: "Stop", terminate: "Terminate" };

function DeviceTokens({ tokens }: { tokens: Record<string, string> }) {
  const entries = Object.entries(tokens);
  if (!entries.length) return null;
  return (
    <div className="notice dep-tokens" role="status">
      <strong>Device tokens</strong>: copy them now, they are not shown again.
      <ul className="plain-list">
        {entries.map(([device, token]) => (
          <li key={device}>
            {device}: <code>{token}</code>
          </li>
        ))}
      </ul>
    </div>
  );
}

interface ActionsProps {
  deployment: Deployment;
  onDone: (runId?: number) => void;
}

function LifecycleActions({ deployment, onDone }: ActionsProps) {
  const [busy, setBusy] = useState(false);
  const [error, setError] = useState<Error | null>(null);
  const [phase, setPhase] = useState<string>("analyze");
  const [purge, setPurge] = useState(false);
  async function act(fn: () => Promise<number | undefined>) {
    setBusy(true);
    setError(null);
    try {
      onDone(await fn());
    } catch (err) {
      setError(err instanceof Error ? err : new Error(String(err)));
    } finally {
      setBusy(false);
    }
  }
  function step(t: Transition) {
    if (t === "terminate") {
      const what = purge ? "its devices, processors, connectors, services, and the twin with its history" : "its devices, processors, connectors and services (the twin's document and history are kept)";
      if (!window.confirm(`Terminate ${deployment.name}? This removes ${what}.`)) return;
    }
    void act(async () => {
      await transition(deployment.name, t, purge);
      return undefined;
    });
  }
  const steps = transitionsOf(deployment.state);
  const live = deployment.state !== "terminated" && deployment.state !== "failed";
  return (
    <div className="dep-actions" aria-label="Lifecycle">
      {steps.map((t) => (
        <button key={t} type="button" disabled={busy} className={t === "terminate" ? "proc-danger" : undefined} onClick={() => step(t)}>
          {LABELS[t]}
        </button>
      ))}
      {steps.includes("terminate") && (
        <label className="sf-check">
          <input type="checkbox" checked={purge} onChange={(e) => setPurge(e.target.checked)} /> purge the twin and its history
        </label>
      )}
      {live && (
        <>
          <label htmlFor="dep-phase">Run phase</label>
          <select id="dep-phase" value={phase} onChange={(e) => setPhase(e.target.value)}>
            {PHASES.map((p) => (
              <option key={p} value={p}>
                {p}
              </option>
            ))}
          </select>
          <button type="button" disabled={busy} onClick={() => void act(async () => (await startRun(deployment.name, phase)).id)}>
            Run
          </button>
        </>
      )}
      {error && <ErrorMessage error={error} />}
    </div>
  );
}

function Resources({ deployment }: { deployment: Deployment }) {
  const r = deployment.resources ?? {};
  const rows: [string, string[] | undefined][] = [
    ["Devices", r.devices],
    ["Processors", r.processors],
    ["Connectors", r.connectors],
    ["Services", r.services],
  ];
  return (
    <dl className="props">
      <dt>Package</dt>
      <dd className="mono">{deployment.package}</dd>
      <dt>Twin</dt>
      <dd>{deployment.state === "terminated" ? deployment.twin : <Link to={`/twins/${encodeURIComponent(deployment.twin)}`}>{deployment.twin}</Link>}</dd>
      <dt>Parameters</dt>
      <dd className="mono">{JSON.stringify(deployment.parameters)}</dd>
      {rows.map(([label, names]) => (
        <div className="prop-row" key={label}>
          <dt>{label}</dt>
          <dd>{names && names.length ? names.join(", ") : "none"}</dd>
        </div>
      ))}
      {deployment.error && (
        <>
          <dt>Error</dt>
          <dd className="proc-error-text">{deployment.error}</dd>
        </>
      )}
    </dl>
  );
}

/** The device tokens handed over by the page that deployed: kept here, and taken out of the
 * history entry at once, so that a reload or going back does not show them again. */
function useHandedTokens(): Record<string, string> {
  const location = useLocation();
  const navigate = useNavigate();
  const [tokens] = useState(() => (location.state as CreatedState | null)?.deviceTokens ?? {});
  useEffect(() => {
    if (location.state) navigate(location.pathname, { replace: true, state: null });
  }, [location.state, location.pathname, navigate]);
  return tokens;
}

interface RunsProps {
  runs: ApiState<Run[]>;
  /** The run whose log is shown; else the active one, if any. */
  selected: number | null;
  onSelect: (id: number) => void;
}

/** Every run of the deployment and the log of one. */
function RunsSection({ runs, selected, onSelect }: RunsProps) {
  const [cancelError, setCancelError] = useState<Error | null>(null);
  const shown = runs.data?.find((r) => r.id === selected) ?? runs.data?.find(isActive) ?? null;
  return (
    <>
      <h2>Runs</h2>
      {runs.error && <ErrorMessage error={runs.error} onRetry={runs.reload} />}
      {cancelError && <ErrorMessage error={cancelError} />}
      {!runs.data && !runs.error && <Loading />}
      {runs.data && (
        <RunHistory
          runs={runs.data}
          selected={shown?.id ?? null}
          onSelect={onSelect}
          onCancel={(id) => {
            setCancelError(null);
            cancelRun(id).then(runs.reload, (err: unknown) => setCancelError(err instanceof Error ? err : new Error(String(err))));
          }}
        />
      )}
      {shown ? <RunLog run={shown} onEnd={runs.reload} /> : runs.data && runs.data.length > 0 && <Empty>Choose “Log” to read a run's log.</Empty>}
    </>
  );
}

export function DeploymentPage() {
  const { name = "" } = useParams();
  const tokens = useHandedTokens();
  const deployment = useApi((signal) => getDeployment(name, signal), [name]);
  const runs = useApi((signal) => listRuns(name, signal), [name]);
  const [selected, setSelected] = useState<number | null>(null);
  const [reconfiguring, setReconfiguring] = useState(false);
  const { reload: reloadDeployment } = deployment;
  const { reload: reloadRuns } = runs;
  useEffect(() => {
    const timer = setInterval(() => {
      reloadDeployment();
      reloadRuns();
    }, REFRESH_MS);
    return () => clearInterval(timer);
  }, [reloadDeployment, reloadRuns]);

  const reloadAll = (runId?: number) => {
    if (runId) setSelected(runId);
    reloadDeployment();
    reloadRuns();
  };
  if (deployment.error && !deployment.data) return <main className="page"><ErrorMessage error={deployment.error} onRetry={deployment.reload} /></main>;
  if (!deployment.data) return <main className="page"><Loading /></main>;
  const d = deployment.data;
  return (
    <main className="page">
      <p>
        <Link to="/deployments">Deployments</Link> /
      </p>
      <h1>
        {d.name} <span className={`badge dep-state-${d.state}`}>{d.state}</span>
      </h1>
      <DeviceTokens tokens={tokens} />
      {deployment.error && <ErrorMessage error={deployment.error} />}
      <LifecycleActions deployment={d} onDone={reloadAll} />
      <Resources deployment={d} />
      {transitionsOf(d.state).length > 0 && !reconfiguring && (
        <button type="button" onClick={() => setReconfiguring(true)}>
          Reconfigure
        </button>
      )}
      {reconfiguring && (
        <Reconfigure
          key={d.package}
          deployment={d}
          onDone={() => {
            setReconfiguring(false);
            reloadAll();
          }}
          onCancel={() => setReconfiguring(false)}
        />
      )}
      <RunsSection runs={runs} selected={selected} onSelect={setSelected} />
    </main>
  );
}
