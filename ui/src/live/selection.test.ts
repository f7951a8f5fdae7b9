import { describe, expect, it } from "vitest";
import type { StreamInfo } from "../api/history";
import { byStream, defaultRefs, formatRefs, knownRefs, parseRefs, parseWindow } from "./selection";

function stream(name: string, signals: [string, StreamInfo["signals"][number]["kind"]][]): StreamInfo {
  return { name, count: 1, first: 1, last: 2, signals: signals.map(([n, kind]) => ({ name: n, kind, count: 1, first: 1, last: 2 })) };
}

const TINGEN = [
  stream("telemetry", [
    ["Input_F_in", "number"],
    ["Cantilever_Angle_radians", "number"],
    ["mode", "string"],
  ]),
  stream("fmu", [
    ["sigma", "number"],
    ["theta", "number"],
  ]),
];

describe("selection", () => {
  it("reads and writes stream:signal lists, signal names may hold colons", () => {
    const refs = parseRefs("telemetry:a,fmu:ns:theta,bad,:x,y:,telemetry:a");
    expect(refs).toEqual([
      { stream: "telemetry", signal: "a" },
      { stream: "fmu", signal: "ns:theta" },
    ]);
    expect(formatRefs(refs)).toBe("telemetry:a,fmu:ns:theta");
    expect(parseRefs(null)).toEqual([]);
  });

  it("chooses the measured and the simulated angle of the demo rig by default", () => {
    expect(defaultRefs(TINGEN)).toEqual([
      { stream: "telemetry", signal: "Cantilever_Angle_radians" },
      { stream: "fmu", signal: "theta" },
    ]);
  });

  it("otherwise chooses the first numeric signals of the first stream that has any", () => {
    const other = [
      stream("log", [["line", "string"]]),
      stream("plc", [
        ["a", "integer"],
        ["b", "string"],
        ["c", "bool"],
        ["d", "number"],
        ["e", "number"],
      ]),
    ];
    expect(defaultRefs(other).map((r) => r.signal)).toEqual(["a", "c", "d"]);
    expect(defaultRefs([stream("log", [["line", "string"]])])).toEqual([]);
  });

  it("keeps only refs the twin has and groups them by stream", () => {
    const refs = knownRefs(TINGEN, parseRefs("telemetry:mode,telemetry:Input_F_in,fmu:theta,gone:x,telemetry:Cantilever_Angle_radians"));
    expect(formatRefs(refs)).toBe("telemetry:Input_F_in,fmu:theta,telemetry:Cantilever_Angle_radians");
    expect([...byStream(refs)]).toEqual([
      ["telemetry", ["Input_F_in", "Cantilever_Angle_radians"]],
      ["fmu", ["theta"]],
    ]);
  });

  it("accepts only the offered windows", () => {
    expect(parseWindow("300")).toBe(300);
    expect(parseWindow("7")).toBe(30);
    expect(parseWindow(null)).toBe(30);
  });
});
