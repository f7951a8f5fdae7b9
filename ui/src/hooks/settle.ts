/** Follow an abortable load: its value to `value`, its failure (as an Error) to `error`, and
 * `done` at the end — none of them once `signal` was aborted, so a load that was replaced
 * never overwrites the newer one. */
export function settle<T>(
  promise: Promise<T>,
  signal: AbortSignal,
  on: { value: (value: T) => void; error: (error: Error) => void; done: () => void },
): void {
  promise
    .then((value) => {
      if (!signal.aborted) on.value(value);
    })
    .catch((err: unknown) => {
      if (!signal.aborted) on.error(err instanceof Error ? err : new Error(String(err)));
    })
    .finally(() => {
      if (!signal.aborted) on.done();
    });
}
