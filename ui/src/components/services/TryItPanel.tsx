import { useState, type FormEvent } from "react";
import { callService, type ServiceCall } from "../../api/gateway";
import type { Service } from "../../api/types";
import { ErrorMessage } from "../common/Status";

const DEFAULT_METHODS = ["GET", "HEAD", "OPTIONS", "POST", "PUT", "PATCH", "DELETE"];
const NO_BODY = new Set(["GET", "HEAD", "OPTIONS"]);

function prettyBody(call: ServiceCall): string {
  if (/json/i.test(call.contentType) && !call.truncated) {
    try {
      return JSON.stringify(JSON.parse(call.body), null, 2);
    } catch {
      // not valid JSON after all: show it as it came
    }
  }
  return call.body;
}

/** Send a request to a twin's service through the gateway and show the answer. */
export function TryItPanel({ slug, service }: { slug: string; service: Pick<Service, "name" | "methods" | "health_path"> }) {
  const methods = service.methods.length ? service.methods : DEFAULT_METHODS;
  const [method, setMethod] = useState(methods[0] ?? "GET");
  const [path, setPath] = useState(service.health_path ?? "");
  const [body, setBody] = useState("");
  const [call, setCall] = useState<ServiceCall>();
  const [error, setError] = useState<Error>();
  const [sending, setSending] = useState(false);
  const hasBody = !NO_BODY.has(method);

  async function send(event: FormEvent) {
    event.preventDefault();
    setError(undefined);
    let payload: string | null = null;
    if (hasBody && body.trim()) {
      try {
        payload = JSON.stringify(JSON.parse(body));
      } catch (err) {
        setError(new Error(`The body is not valid JSON: ${err instanceof Error ? err.message : String(err)}`));
        return;
      }
    }
    setSending(true);
    try {
      setCall(await callService(slug, service.name, method, path, payload));
    } catch (err) {
      setCall(undefined);
      setError(new Error(`The request failed before an answer came: ${err instanceof Error ? err.message : String(err)}`));
    } finally {
      setSending(false);
    }
  }

  return (
    <form className="try-it" onSubmit={(e) => void send(e)} aria-label={`Try ${service.name}`}>
      <div className="try-it-row">
        <select aria-label="Method" value={method} onChange={(e) => setMethod(e.target.value)}>
          {methods.map((m) => (
            <option key={m}>{m}</option>
          ))}
        </select>
        <span className="mono muted">/twins/{slug}/services/{service.name}/</span>
        <input aria-label="Path" className="mono" value={path} placeholder="path?query" onChange={(e) => setPath(e.target.value)} />
        <button type="submit" disabled={sending}>
          {sending ? "Sending…" : "Send"}
        </button>
      </div>
      {hasBody && (
        <textarea
          aria-label="JSON body"
          className="mono"
          rows={4}
          placeholder='{"optional": "JSON body"}'
          value={body}
          onChange={(e) => setBody(e.target.value)}
        />
      )}
      {error && <ErrorMessage error={error} />}
      {call && <TryItAnswer call={call} />}
    </form>
  );
}

/** The answer of the last call: status, time, type, size and the (pretty-printed) body. */
function TryItAnswer({ call }: { call: ServiceCall }) {
  const ok = call.status >= 200 && call.status < 300;
  return (
    <div className="try-it-answer" data-testid="try-it-answer">
      <div className="try-it-meta">
        <span className={ok ? "status status-ok" : "status status-bad"}>
          {call.status} {call.statusText}
        </span>
        <span>{call.ms.toFixed(1)} ms</span>
        <span className="mono">{call.contentType || "no content type"}</span>
        <span>{call.size.toLocaleString()} characters</span>
      </div>
      {call.truncated && <p className="muted">The answer is long; only its first {call.body.length.toLocaleString()} characters are shown.</p>}
      {call.body ? <pre className="answer-body">{prettyBody(call)}</pre> : <p className="muted">(empty body)</p>}
    </div>
  );
}
