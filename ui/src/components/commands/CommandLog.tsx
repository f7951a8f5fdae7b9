import { useState } from "react";
import { COMMAND_STATES, listCommands, type CommandRecord, type CommandState } from "../../api/commands";
import { useApi } from "../../hooks/useApi";
import { Empty, ErrorMessage, Loading, formatTime } from "../common/Status";
import { durationMs, formatDuration, StateBadge } from "./CommandOutcome";
import { compactJson } from "./commandForm";

const LIMIT = 100;

function outcomeText(c: CommandRecord): string {
  if (c.error) return c.error;
  return compactJson(c.result ?? undefined);
}

function LogTable({ commands }: { commands: CommandRecord[] }) {
  return (
    <table className="table command-log">
      <thead>
        <tr>
          <th>Sent</th>
          <th>Command</th>
          <th>Arguments</th>
          <th>Device</th>
          <th>State</th>
          <th className="num">Took</th>
          <th>Result or error</th>
          <th>By</th>
        </tr>
      </thead>
      <tbody>
        {commands.map((c) => (
          <tr key={c.id}>
            <td title={c.id}>{formatTime(c.created)}</td>
            <td className="mono">{c.name}</td>
            <td className="mono clip">{compactJson(c.args)}</td>
            <td className="mono">{c.device}</td>
            <td>
              <StateBadge state={c.state} />
              {c.queued && <span className="muted"> queued</span>}
            </td>
            <td className="num">{formatDuration(durationMs(c))}</td>
            <td className={`mono clip${c.error ? " status-bad" : ""}`} title={outcomeText(c)}>
              {outcomeText(c)}
            </td>
            <td>{c.sent_by ?? ""}</td>
          </tr>
        ))}
      </tbody>
    </table>
  );
}

/** The twin's command log, newest first, with a state filter and a refresh button. */
export function CommandLog({ slug, refreshKey }: { slug: string; refreshKey: number }) {
  const [state, setState] = useState<CommandState | "">("");
  const log = useApi((signal) => listCommands(slug, { state, limit: LIMIT }, signal), [slug, state, refreshKey]);

  return (
    <>
      <div className="log-toolbar">
        <label>
          State{" "}
          <select value={state} onChange={(e) => setState(e.target.value as CommandState | "")}>
            <option value="">all</option>
            {COMMAND_STATES.map((s) => (
              <option key={s}>{s}</option>
            ))}
          </select>
        </label>
        <button type="button" onClick={log.reload} disabled={log.loading}>
          {log.loading ? "Loading…" : "Refresh"}
        </button>
        <span className="muted">the newest {LIMIT}</span>
      </div>
      {log.error ? (
        <ErrorMessage error={log.error} onRetry={log.reload} />
      ) : !log.data ? (
        <Loading what="Loading the command log" />
      ) : log.data.length === 0 ? (
        <Empty>{state ? `No ${state} commands.` : "No command has been sent to this twin yet."}</Empty>
      ) : (
        <LogTable commands={log.data} />
      )}
    </>
  );
}
