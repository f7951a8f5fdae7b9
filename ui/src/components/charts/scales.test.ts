import { describe, expect, it } from "vitest";
import { assignScales, magnitude } from "./scales";

describe("assignScales", () => {
  it("keeps series of similar size on one axis", () => {
    expect(assignScales([0.3, 0.12, 2])).toEqual(["y", "y", "y"]);
  });

  it("puts series orders of magnitude apart on a second axis, the first one's side on the left", () => {
    expect(assignScales([7e7, 0.1, 0.3])).toEqual(["y", "y2", "y2"]);
    expect(assignScales([0.1, 7e7, 0.3, 2e6])).toEqual(["y", "y2", "y", "y2"]);
  });

  it("leaves series without values on the left", () => {
    expect(assignScales([0, 0.1, 5000])).toEqual(["y", "y", "y2"]);
    expect(assignScales([])).toEqual([]);
  });

  it("measures the largest absolute value", () => {
    expect(magnitude([null, -4, 3, undefined])).toBe(4);
    expect(magnitude([])).toBe(0);
  });
});
