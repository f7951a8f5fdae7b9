import { describe, expect, it } from "vitest";
import { mapLimited } from "./mapLimited";

describe("mapLimited", () => {
  it("keeps at most `limit` calls in flight and answers every outcome in order", async () => {
    let inFlight = 0;
    let most = 0;
    const settled: number[] = [];
    const results = await mapLimited(
      [1, 2, 3, 4, 5, 6, 7],
      3,
      async (n) => {
        inFlight += 1;
        most = Math.max(most, inFlight);
        await new Promise((resolve) => setTimeout(resolve, n % 3));
        inFlight -= 1;
        if (n === 4) throw new Error("four");
        return n * 10;
      },
      { onSettled: (done) => settled.push(done) },
    );
    expect(most).toBe(3);
    expect(results.map((r) => (r.status === "fulfilled" ? r.value : (r.reason as Error).message))).toEqual([
      10, 20, 30, "four", 50, 60, 70,
    ]);
    expect(settled).toEqual([1, 2, 3, 4, 5, 6, 7]);
  });

  it("starts nothing more once aborted, and copes with no items", async () => {
    const controller = new AbortController();
    const started: number[] = [];
    const results = await mapLimited(
      [1, 2, 3],
      1,
      async (n) => {
        started.push(n);
        controller.abort();
        return n;
      },
      { signal: controller.signal },
    );
    expect(started).toEqual([1]);
    expect(results.map((r) => r.status)).toEqual(["fulfilled", "rejected", "rejected"]);
    expect(await mapLimited([], 4, async () => 1)).toEqual([]);
  });
});
