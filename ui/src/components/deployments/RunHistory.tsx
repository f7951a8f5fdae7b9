// Every run of a deployment, newest first: phase, state, exit code, who and when.
import type { Run } from "../../api/deployments";
import { formatEpochMs } from "../common/time";

function when(ns: number | null): string {
  return ns ? formatEpochMs(ns / 1e6) : "—";
}

interface Props {
  runs: Run[];
  selected: number | null;
  onSelect: (id: number) => void;
  onCancel: (id: number) => void;
}

export function RunHistory({ runs, selected, onSelect, onCancel }: Props) {
  if (!runs.length) return <p className="muted">No run yet.</p>;
  return (
    <div className="table-scroll">
      <table className="table" aria-label="Runs">
        <thead>
          <tr>
            <th>Run</th>
            <th>Phase</th>
            <th>State</th>
            <th className="num">Exit code</th>
            <th>Queued</th>
            <th>Started</th>
            <th>Ended</th>
            <th>By</th>
            <th>
              <span className="visually-hidden">Actions</span>
            </th>
          </tr>
        </thead>
        <tbody>
          {runs.map((run) => (
            <tr key={run.id} className={run.id === selected ? "proc-row-open" : undefined}>
              <td className="mono">{run.id}</td>
              <td>{run.phase}</td>
              <td>
                <span className={`badge run-${run.state}`}>{run.state}</span>
                {run.error && run.error !== run.state && <div className="proc-error-text">{run.error}</div>}
              </td>
              <td className="num">{run.exit_code ?? "—"}</td>
              <td>{when(run.created_ns)}</td>
              <td>{when(run.started_ns)}</td>
              <td>{when(run.ended_ns)}</td>
              <td>{run.started_by}</td>
              <td className="nowrap">
                <button type="button" className="link-button" aria-pressed={run.id === selected} aria-label={`Log of ${run.phase} run ${run.id}`} onClick={() => onSelect(run.id)}>
                  Log
                </button>
                {(run.state === "queued" || run.state === "running") && (
                  <button type="button" className="link-button" aria-label={`Cancel ${run.phase} run ${run.id}`} onClick={() => onCancel(run.id)}>
                    Cancel
                  </button>
                )}
              </td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
