import { useEffect } from "react";
import { getCommand, isOpen, type CommandRecord } from "../../api/commands";

const POLL_MS = 1500;

/** The milliseconds from sending to the end, when the command has ended. */
export function durationMs(record: CommandRecord): number | null {
  if (!record.finished) return null;
  const ms = Date.parse(record.finished) - Date.parse(record.created);
  return Number.isFinite(ms) ? ms : null;
}

export function formatDuration(ms: number | null): string {
  if (ms === null) return "";
  return ms < 1000 ? `${ms} ms` : `${(ms / 1000).toFixed(ms < 10_000 ? 2 : 1)} s`;
}

export function StateBadge({ state }: { state: CommandRecord["state"] }) {
  return <span className={`badge state-${state}`}>{state}</span>;
}

/** Check an unfinished command again now and then until it has ended. */
function usePollWhileOpen(slug: string, record: CommandRecord, onUpdate: (r: CommandRecord) => void) {
  const open = isOpen(record);
  useEffect(() => {
    if (!open) return;
    const controller = new AbortController();
    const timer = setTimeout(() => {
      getCommand(slug, record.id, controller.signal)
        .then((fresh) => {
          if (!controller.signal.aborted) onUpdate(fresh);
        })
        .catch(() => {
          // a failed check is tried again by the next state change or the user's refresh
        });
    }, POLL_MS);
    return () => {
      clearTimeout(timer);
      controller.abort();
    };
  }, [slug, record, open, onUpdate]);
}

/** The result of one command: state, duration, the returned JSON or the error. */
export function CommandOutcome({
  slug,
  record,
  onUpdate,
}: {
  slug: string;
  record: CommandRecord;
  onUpdate: (r: CommandRecord) => void;
}) {
  usePollWhileOpen(slug, record, onUpdate);
  const duration = formatDuration(durationMs(record));
  return (
    <div className="command-outcome" data-testid="command-outcome" aria-live="polite">
      <div className="outcome-meta">
        <StateBadge state={record.state} />
        <span className="mono">{record.device}</span>
        {duration && <span>took {duration}</span>}
        {record.queued && <span className="muted">queued</span>}
        {isOpen(record) && <span className="muted">waiting for the device…</span>}
        <span className="muted mono">id {record.id}</span>
      </div>
      {record.error && (
        <p className="outcome-error">
          <strong>Error:</strong> {record.error}
        </p>
      )}
      {record.result !== null && record.result !== undefined && (
        <pre className="answer-body outcome-result">{JSON.stringify(record.result, null, 2)}</pre>
      )}
      {record.late_status && (
        <p className="muted">
          A late answer ({record.late_status}) came after the command had expired; it is shown above.
        </p>
      )}
    </div>
  );
}
