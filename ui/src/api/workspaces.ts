// The caller's JupyterLab workspace (issue 16).
import { apiFetch } from "./client";

export interface Workspace {
  user: string;
  /** starting, running, stopping, stopped or failed */
  state: string;
  /** /workspaces/<user>/?ticket=...: a one-time ticket the proxy swaps for a cookie; only
   * while it runs. */
  url: string | null;
  /** Why it failed. */
  error?: string | null;
  /** The last lines of its log, when it failed. */
  log?: string[];
}

/** Start the caller's workspace (a no-op when it runs) and answer where it is. */
export function startWorkspace(): Promise<Workspace> {
  return apiFetch<Workspace>("/api/v1/workspaces/me", { method: "POST" });
}
