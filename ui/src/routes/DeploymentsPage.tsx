// Deployments of twin packages: the list with their states, and "New deployment".
import { useState } from "react";
import { Link, useNavigate } from "react-router-dom";
import { listDeployments, type CreateAnswer } from "../api/deployments";
import { Empty, ErrorMessage, Loading } from "../components/common/Status";
import { formatEpochMs } from "../components/common/time";
import { NewDeployment } from "../components/deployments/NewDeployment";
import { useApi } from "../hooks/useApi";
import "../components/processors/processors.css";
import "../components/deployments/deployments.css";

/** Device tokens are shown once, when the deployment is made: handed to its page this way. */
export interface CreatedState {
  deviceTokens: Record<string, string>;
}

export function DeploymentsPage() {
  const deployments = useApi((signal) => listDeployments(signal), []);
  const [creating, setCreating] = useState(false);
  const navigate = useNavigate();

  function created(answer: CreateAnswer) {
    const state: CreatedState = { deviceTokens: answer.device_tokens ?? {} };
    navigate(`/deployments/${encodeURIComponent(answer.deployment.name)}`, { state });
  }

  return (
    <main className="page">
      <div className="dep-toolbar">
        <h1>Deployments</h1>
        <span className="spacer" />
        {!creating && (
          <button type="button" onClick={() => setCreating(true)}>
            New deployment
          </button>
        )}
      </div>
      <p className="muted">Twins made from a twin package of the library, with their lifecycle runs.</p>
      {creating && <NewDeployment onCreated={created} onCancel={() => setCreating(false)} />}
      {deployments.error && <ErrorMessage error={deployments.error} onRetry={deployments.reload} />}
      {!deployments.data && !deployments.error && <Loading />}
      {deployments.data && deployments.data.length === 0 && <Empty>No deployment yet: choose “New deployment” to make one from a twin package.</Empty>}
      {deployments.data && deployments.data.length > 0 && (
        <div className="table-scroll">
          <table className="table" aria-label="Deployments">
            <thead>
              <tr>
                <th>Name</th>
                <th>State</th>
                <th>Package</th>
                <th>Twin</th>
                <th>By</th>
                <th>Changed</th>
              </tr>
            </thead>
            <tbody>
              {deployments.data.map((d) => (
                <tr key={d.id}>
                  <td>
                    <Link to={`/deployments/${encodeURIComponent(d.name)}`}>{d.name}</Link>
                  </td>
                  <td>
                    <span className={`badge dep-state-${d.state}`}>{d.state}</span>
                  </td>
                  <td className="mono">{d.package_ref}</td>
                  <td>{d.state === "terminated" ? d.twin : <Link to={`/twins/${encodeURIComponent(d.twin)}`}>{d.twin}</Link>}</td>
                  <td>{d.created_by}</td>
                  <td>{formatEpochMs(d.updated_ns / 1e6)}</td>
                </tr>
              ))}
            </tbody>
          </table>
        </div>
      )}
    </main>
  );
}
