import { useRef, useState } from "react";
import "./admin.css";

/** A secret (a token) shown once, with a copy button. It lives only in the caller's state:
 * never put it in sessionStorage, localStorage or a log. `onDone` should forget it. */
export function SecretOnce({ title, secret, onDone }: { title: string; secret: string; onDone: () => void }) {
  const input = useRef<HTMLInputElement>(null);
  const [copied, setCopied] = useState<"yes" | "no" | null>(null);

  async function copy() {
    try {
      // The clipboard API exists only in secure contexts (https or localhost).
      if (!navigator.clipboard) throw new Error("no clipboard");
      await navigator.clipboard.writeText(secret);
      setCopied("yes");
    } catch {
      input.current?.select();
      setCopied("no");
    }
  }

  return (
    <div className="secret-once" role="region" aria-label={title}>
      <strong>{title}</strong>
      <p className="secret-warning">
        Copy it now: it is shown only this once and cannot be shown again. If it is lost, make a new one.
      </p>
      <div className="secret-row">
        <input
          ref={input}
          className="mono"
          readOnly
          value={secret}
          aria-label="Secret"
          onFocus={(e) => e.currentTarget.select()}
          data-testid="secret-value"
        />
        <button type="button" onClick={() => void copy()}>
          Copy
        </button>
        <button type="button" onClick={onDone}>
          I have saved it
        </button>
      </div>
      {copied === "yes" && <span className="doc-ok">Copied to the clipboard.</span>}
      {copied === "no" && <span className="muted">The browser would not copy it; it is selected, copy it by hand.</span>}
    </div>
  );
}
