// "Workspace": start the user's JupyterLab (a no-op when it runs) and open it in a new tab.
// The tab is opened at the click, before the answer, so that pop-up blockers let it through;
// it is then sent to the one-time URL (or closed, when the workspace cannot start).
import { useState } from "react";
import { startWorkspace } from "../../api/workspaces";

export function WorkspaceLink() {
  const [error, setError] = useState<string | null>(null);
  const [busy, setBusy] = useState(false);
  async function open() {
    setError(null);
    setBusy(true);
    const tab = window.open("about:blank", "_blank");
    try {
      const { url, state, error: why } = await startWorkspace();
      if (!url) throw new Error(why ? `it is ${state}: ${why}` : `it is ${state}; try again in a moment`);
      if (tab) {
        // The new tab must not reach back into this one through window.opener.
        tab.opener = null;
        tab.location.href = url;
      } else window.location.assign(url);
    } catch (err) {
      tab?.close();
      setError(err instanceof Error ? err.message : String(err));
    } finally {
      setBusy(false);
    }
  }
  return (
    <>
      <button type="button" className="header-link" disabled={busy} onClick={() => void open()} title="Your JupyterLab, opened in a new tab">
        {busy ? "Starting…" : "Workspace"}
      </button>
      {error && (
        <span className="header-error" role="alert">
          The workspace did not start: {error}
        </span>
      )}
    </>
  );
}
