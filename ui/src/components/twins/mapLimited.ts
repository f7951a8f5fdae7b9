/** Run `fn` over `items` with at most `limit` calls in flight, and answer every outcome in the
 * order of `items`; one failure does not stop the others. `onSettled` hears how many are done.
 * Once `signal` is aborted no further call starts (those not started answer the abort). */
export async function mapLimited<T, R>(
  items: readonly T[],
  limit: number,
  fn: (item: T) => Promise<R>,
  options: { signal?: AbortSignal; onSettled?: (done: number) => void } = {},
): Promise<PromiseSettledResult<R>[]> {
  const results: PromiseSettledResult<R>[] = [];
  let next = 0;
  let done = 0;
  const worker = async () => {
    while (next < items.length) {
      const index = next++;
      try {
        options.signal?.throwIfAborted();
        results[index] = { status: "fulfilled", value: await fn(items[index] as T) };
      } catch (reason) {
        results[index] = { status: "rejected", reason };
      }
      done += 1;
      options.onSettled?.(done);
    }
  };
  await Promise.all(Array.from({ length: Math.max(1, Math.min(limit, items.length)) }, worker));
  return results;
}
