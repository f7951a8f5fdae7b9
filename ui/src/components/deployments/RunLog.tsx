// A run's log: the whole of it, followed live over the run's WebSocket while the run is active
// (the socket sends what was logged so far, then each chunk as it comes, as binary frames, then
// a text frame with the end state as JSON). A socket that drops while the run goes on is opened
// again from the byte the log had reached. A finished run's log is read once; reopening the page
// shows all of it again.
import { useEffect, useRef, useState } from "react";
import { authMessage, endFrame, isActive, logSocketUrl, readLog, type Run, type RunState } from "../../api/deployments";
import { ErrorMessage } from "../common/Status";

/** How long to wait before following again after the socket dropped (doubled up to 10 s). */
export const RECONNECT_MS = 500;
const MAX_RECONNECT_MS = 10_000;
/** The socket's close codes that say following again would not help. */
const FINAL_CLOSE = new Set([1000, 4401, 4404]);

/** The longest log text kept in the page; older text is cut (the full log stays on the server). */
export const MAX_LOG_CHARS = 2_000_000;

interface End {
  state: RunState;
  exit_code: number | null;
}

function useRunLog(run: Run, onEnd: () => void) {
  const [text, setText] = useState("");
  const [error, setError] = useState<Error | null>(null);
  const [end, setEnd] = useState<End | null>(null);
  const onEndRef = useRef(onEnd);
  onEndRef.current = onEnd;
  const active = isActive(run);
  useEffect(() => {
    setText("");
    setEnd(null);
    setError(null);
    const controller = new AbortController();
    const readAll = () =>
      readLog(run.id, 0, controller.signal).then(
        (log) => !controller.signal.aborted && setText(log.text.slice(-MAX_LOG_CHARS)),
        (err: unknown) => !controller.signal.aborted && setError(err instanceof Error ? err : new Error(String(err))),
      );
    if (!active) {
      void readAll();
      return () => controller.abort();
    }
    let received = 0; // bytes of the log taken in: where to follow again from
    let wait = RECONNECT_MS;
    let socket: WebSocket | null = null;
    let timer: ReturnType<typeof setTimeout> | undefined;
    // A chunk may end inside a character of several bytes: the decoder keeps it for the next.
    const decoder = new TextDecoder();
    const follow = () => {
      const ws = new WebSocket(logSocketUrl(run.id, received));
      socket = ws;
      ws.binaryType = "arraybuffer";
      ws.onopen = () => ws.send(authMessage());
      ws.onmessage = (event: MessageEvent) => {
        const data: unknown = event.data;
        wait = RECONNECT_MS;
        if (typeof data === "string") {
          const frame = endFrame(data);
          if (frame) {
            setEnd(frame);
            onEndRef.current();
          }
          return;
        }
        const bytes = data as ArrayBuffer;
        received += bytes.byteLength;
        const chunk = decoder.decode(bytes, { stream: true });
        setText((t) => (t + chunk).slice(-MAX_LOG_CHARS));
      };
      ws.onclose = (event: CloseEvent) => {
        if (controller.signal.aborted) return;
        if (!FINAL_CLOSE.has(event.code)) {
          timer = setTimeout(follow, wait);
          wait = Math.min(wait * 2, MAX_RECONNECT_MS);
          return;
        }
        // The authoritative text is the stored log: read it whole once the socket is done.
        void readAll();
        if (event.code !== 1000) setError(new Error(`The live log ended: ${event.reason || `closed with ${event.code}`}`));
      };
    };
    follow();
    return () => {
      controller.abort();
      clearTimeout(timer);
      socket?.close();
    };
  }, [run.id, active]);
  return { text, error, end };
}

export function RunLog({ run, onEnd }: { run: Run; onEnd: () => void }) {
  const { text, error, end } = useRunLog(run, onEnd);
  const box = useRef<HTMLPreElement>(null);
  useEffect(() => {
    const el = box.current;
    if (el) el.scrollTop = el.scrollHeight;
  }, [text]);
  const state = end?.state ?? run.state;
  const exit = end ? end.exit_code : run.exit_code;
  return (
    <section aria-label={`Log of run ${run.id}`} className="run-log">
      <h4>
        Log of {run.phase} <span className="mono">{run.id}</span>: <span className={`badge run-${state}`}>{state}</span>
        {exit !== null && exit !== undefined && <span className="muted"> exit code {exit}</span>}
      </h4>
      {error && <ErrorMessage error={error} />}
      <pre ref={box} className="proc-logs" tabIndex={0} aria-live="polite" data-testid="run-log">
        {text || (isActive({ state }) ? "Waiting for output…" : "(no output)")}
      </pre>
    </section>
  );
}
