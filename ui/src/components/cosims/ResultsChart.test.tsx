import { afterEach, describe, expect, it, vi } from "vitest";
import { render, waitFor } from "@testing-library/react";
import type uPlot from "uplot";
import { FakeUplot } from "../charts/fakeUplot";
import { isZoomed, ResultsChart, SHOWN_AT_FIRST } from "./ResultsChart";

vi.mock("uplot", async () => (await import("../charts/fakeUplot")).fakeUplotModule);

afterEach(() => {
  vi.restoreAllMocks();
  FakeUplot.instances = [];
});

const results = (n: number, columns = 2) => ({
  columns: ["time", ...Array.from({ length: columns }, (_, i) => `m.y${i}`)],
  data: [Array.from({ length: n }, (_, i) => i * 0.5), ...Array.from({ length: columns }, () => Array.from({ length: n }, () => 1))],
});

/** uPlot's setScale hook, as a user's zoom (or uPlot's reset) calls it. */
function scaled(chart: FakeUplot, min: number, max: number) {
  Object.assign(chart, { scales: { x: { min, max } } });
  for (const hook of chart.opts.hooks?.setScale ?? []) hook?.(chart as unknown as uPlot, "x");
}

describe("isZoomed", () => {
  it("says whether the x axis shows less than the whole data", () => {
    const data = [[0, 1, 2]] as unknown as uPlot.AlignedData;
    expect(isZoomed({ data, scales: { x: { min: 0, max: 2 } } })).toBe(false);
    expect(isZoomed({ data, scales: { x: { min: 0.5, max: 2 } } })).toBe(true);
    expect(isZoomed({ data, scales: { x: { min: 0, max: 1.5 } } })).toBe(true);
    expect(isZoomed({ data: [[]] as unknown as uPlot.AlignedData, scales: { x: {} } })).toBe(false);
  });
});

describe("ResultsChart", () => {
  it("shows the first columns, lists the others to be shown by a click in the legend", async () => {
    render(<ResultsChart results={results(3, SHOWN_AT_FIRST + 2)} />);
    await waitFor(() => expect(FakeUplot.instances).toHaveLength(1));
    const shown = FakeUplot.instances[0]!.opts.series.slice(1).map((s) => s.show);
    expect(shown).toEqual([...Array(SHOWN_AT_FIRST).fill(true), false, false]);
  });

  it("takes new rows in place, keeping a zoom the user chose until they zoom out", async () => {
    const view = render(<ResultsChart results={results(3)} />);
    await waitFor(() => expect(FakeUplot.instances).toHaveLength(1));
    const chart = FakeUplot.instances[0]!;
    const setData = vi.spyOn(chart, "setData");
    view.rerender(<ResultsChart results={results(5)} />);
    expect(setData).toHaveBeenLastCalledWith(results(5).data, true);
    scaled(chart, 0.5, 1); // dragged over a part
    view.rerender(<ResultsChart results={results(7)} />);
    expect(setData).toHaveBeenLastCalledWith(results(7).data, false);
    expect(FakeUplot.instances).toHaveLength(1); // the same chart, not made again
    scaled(chart, 0, 3); // a double-click: the whole data again
    view.rerender(<ResultsChart results={results(9)} />);
    expect(setData).toHaveBeenLastCalledWith(results(9).data, true);
  });

  it("is made again when the columns change (a run of another system)", async () => {
    const view = render(<ResultsChart results={results(3)} />);
    await waitFor(() => expect(FakeUplot.instances).toHaveLength(1));
    view.rerender(<ResultsChart results={results(3, 3)} />);
    await waitFor(() => expect(FakeUplot.instances).toHaveLength(2));
    expect(FakeUplot.instances[0]!.destroyed).toBe(true);
    expect(FakeUplot.instances[1]!.opts.series).toHaveLength(4);
  });
});
