// A processor's events (newest first) and the last lines its worker printed.
import { useEffect, useRef } from "react";
import { getProcessorLogs, listProcessorEvents } from "../../api/processors";
import { Empty, ErrorMessage, Loading } from "../common/Status";
import { formatNs } from "./format";
import { usePolled } from "./usePolled";

const BAD_EVENTS = new Set(["crashed", "failed", "memory_limit", "hung", "alarm", "command_failed"]);

export function ProcessorEvents({ slug, name }: { slug: string; name: string }) {
  const events = usePolled((signal) => listProcessorEvents(slug, name, signal), [slug, name]);
  if (!events.data) return events.error ? <ErrorMessage error={events.error} onRetry={events.reload} /> : <Loading what="Loading events" />;
  if (!events.data.length) return <Empty>No events yet.</Empty>;
  return (
    <div className="proc-scroll">
      <table className="table" aria-label="Events">
        <thead>
          <tr>
            <th>Time</th>
            <th>Kind</th>
            <th>Message</th>
          </tr>
        </thead>
        <tbody>
          {events.data.map((e) => (
            <tr key={e.id}>
              <td className="proc-nowrap">{formatNs(e.time_ns)}</td>
              <td>
                <span className={BAD_EVENTS.has(e.kind) ? "badge badge-bad" : "badge"}>{e.kind}</span>
              </td>
              <td className="proc-message">{e.message}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}

export function ProcessorLogs({ slug, name }: { slug: string; name: string }) {
  const logs = usePolled((signal) => getProcessorLogs(slug, name, signal), [slug, name]);
  const pre = useRef<HTMLPreElement>(null);
  const count = logs.data?.length ?? 0;
  useEffect(() => {
    // Follow new lines like a terminal does.
    if (pre.current) pre.current.scrollTop = pre.current.scrollHeight;
  }, [count]);
  if (!logs.data) return logs.error ? <ErrorMessage error={logs.error} onRetry={logs.reload} /> : <Loading what="Loading logs" />;
  if (!logs.data.length) return <Empty>The worker has printed nothing (or is not running).</Empty>;
  return (
    <pre className="proc-logs" ref={pre} tabIndex={0} aria-label="Logs">
      {logs.data.map((line) => line.text).join("\n")}
    </pre>
  );
}
