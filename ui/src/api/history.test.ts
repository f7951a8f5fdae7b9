import { describe, expect, it } from "vitest";
import { aggregateQuery, downsampleQuery, fileNameFrom, isPlottable } from "./history";

describe("history API helpers", () => {
  it("reads the file name of a Content-Disposition header", () => {
    expect(fileNameFrom('attachment; filename="tingen-telemetry.csv"')).toBe("tingen-telemetry.csv");
    expect(fileNameFrom("attachment; filename=tingen-fmu.jsonl")).toBe("tingen-fmu.jsonl");
    expect(fileNameFrom("attachment; filename*=UTF-8''t%C3%A4st.csv")).toBe("täst.csv");
    expect(fileNameFrom("attachment")).toBeNull();
    expect(fileNameFrom(null)).toBeNull();
  });

  it("builds the query of a downsample and an aggregate", () => {
    expect(downsampleQuery(["a", "b"], { start: "-1h" }, 1599.6)).toEqual({ points: 1600, start: "-1h", end: undefined, signals: "a,b" });
    expect(downsampleQuery(["a"], {}, 1).points).toBe(2);
    expect(aggregateQuery(["a"], { start: "x", end: "y" }, "1m", "max")).toEqual({ bucket: "1m", fn: "max", start: "x", end: "y", signals: "a" });
  });

  it("plots numbers, integers and bools, not text", () => {
    expect(["integer", "number", "bool", "string", "mixed"].map((k) => isPlottable(k as never))).toEqual([true, true, true, false, false]);
  });
});
