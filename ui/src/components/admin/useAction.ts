import { useCallback, useState } from "react";

function asError(err: unknown): Error {
  return err instanceof Error ? err : new Error(String(err));
}

/** Run one change at a time (a create, a delete...) and keep its error for showing. */
export function useAction() {
  const [busy, setBusy] = useState(false);
  const [error, setError] = useState<Error>();

  /** Run `fn`; answers whether it succeeded (its error is kept in `error`). */
  const run = useCallback(async (fn: () => Promise<unknown>): Promise<boolean> => {
    setBusy(true);
    setError(undefined);
    try {
      await fn();
      return true;
    } catch (err) {
      setError(asError(err));
      return false;
    } finally {
      setBusy(false);
    }
  }, []);

  const clearError = useCallback(() => setError(undefined), []);
  return { busy, error, run, setError, clearError };
}
