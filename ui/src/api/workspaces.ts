// The caller's JupyterLab workspace (issue 16).
import { apiFetch } from "./client";
import type { Schemas } from "./types";

/** A workspace: `url` (/workspaces/<user>/?ticket=..., a one-time ticket the proxy swaps for a
 * cookie) only while it runs; `error` and `log` say why it failed. */
export type Workspace = Schemas["WorkspaceView"];

/** Start the caller's workspace (a no-op when it runs) and answer where it is. */
export function startWorkspace(): Promise<Workspace> {
  return apiFetch<Workspace>("/api/v1/workspaces/me", { method: "POST" });
}
