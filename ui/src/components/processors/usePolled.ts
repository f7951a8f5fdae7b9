import { useEffect } from "react";
import { useApi, type ApiState } from "../../hooks/useApi";

export const POLL_MS = 3000;

/** useApi that loads again every `intervalMs` while mounted; unmounting aborts the load in
 * flight and stops the timer. The last data stays shown while the next load runs. */
export function usePolled<T>(fn: (signal: AbortSignal) => Promise<T>, deps: unknown[], intervalMs = POLL_MS): ApiState<T> {
  const state = useApi(fn, deps);
  const { reload } = state;
  useEffect(() => {
    const timer = window.setInterval(reload, intervalMs);
    return () => window.clearInterval(timer);
  }, [reload, intervalMs]);
  return state;
}
