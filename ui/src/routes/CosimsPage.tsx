// Co-simulations: the list with their states and progress, and "New co-simulation" (upload a
// file to make one).
import { useState } from "react";
import { Link, useNavigate } from "react-router-dom";
import { listCosims, type Cosim } from "../api/cosims";
import { Empty, ErrorMessage, Loading } from "../components/common/Status";
import { formatWhen, Progress, StateBadge } from "../components/cosims/CosimBits";
import { NewCosim } from "../components/cosims/NewCosim";
import { usePolled } from "../components/processors/usePolled";
import "../components/processors/processors.css";
import "../components/deployments/deployments.css";
import "../components/cosims/cosims.css";

/** Handed to the new co-simulation's page: why it would not start, if it would not. */
export interface CreatedState {
  startError?: string;
}

/** How often the list is read again (states and progress move while a run goes on). */
export const LIST_REFRESH_MS = 2000;

export function CosimsPage() {
  const cosims = usePolled((signal) => listCosims(signal), [], LIST_REFRESH_MS);
  const [creating, setCreating] = useState(false);
  const navigate = useNavigate();

  function created(cosim: Cosim, startError?: string) {
    const state: CreatedState = { startError };
    navigate(`/cosims/${encodeURIComponent(String(cosim.id))}`, { state });
  }

  return (
    <main className="page">
      <div className="dep-toolbar">
        <h1>Co-simulations</h1>
        <span className="spacer" />
        {!creating && (
          <button type="button" onClick={() => setCreating(true)}>
            New co-simulation
          </button>
        )}
      </div>
      <p className="muted">Several FMUs stepped together by a master algorithm, each run in a process of its own on the server.</p>
      {creating && <NewCosim onCreated={created} onCancel={() => setCreating(false)} />}
      {cosims.error && <ErrorMessage error={cosims.error} onRetry={cosims.reload} />}
      {!cosims.data && !cosims.error && <Loading />}
      {cosims.data && cosims.data.length === 0 && <Empty>No co-simulation yet: choose “New co-simulation” and upload a Maestro multi-model, a YAML file or an SSP archive.</Empty>}
      {cosims.data && cosims.data.length > 0 && (
        <div className="table-scroll">
          <table className="table" aria-label="Co-simulations">
            <thead>
              <tr>
                <th>Name</th>
                <th>State</th>
                <th>Progress</th>
                <th>Mode</th>
                <th>Instances</th>
                <th>Twin</th>
                <th>Owner</th>
                <th>Created</th>
              </tr>
            </thead>
            <tbody>
              {cosims.data.map((c) => (
                <tr key={String(c.id)}>
                  <td>
                    <Link to={`/cosims/${encodeURIComponent(String(c.id))}`}>{c.name}</Link>
                  </td>
                  <td>
                    <StateBadge state={c.state} />
                  </td>
                  <td>
                    <Progress cosim={c} />
                  </td>
                  <td>{c.mode === "realtime" ? `real time ×${c.factor}` : c.mode}</td>
                  <td>{c.system?.instances?.length ?? ""}</td>
                  <td>{c.twin ? <Link to={`/twins/${encodeURIComponent(c.twin)}`}>{c.twin}</Link> : <span className="muted">none</span>}</td>
                  <td>{c.owner}</td>
                  <td>{formatWhen(c.created_at)}</td>
                </tr>
              ))}
            </tbody>
          </table>
        </div>
      )}
    </main>
  );
}
