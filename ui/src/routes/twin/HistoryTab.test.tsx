import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { act, fireEvent, screen, waitFor } from "@testing-library/react";
import { setToken } from "../../api/client";
import type { StreamInfo } from "../../api/history";
import { FakeUplot } from "../../components/charts/fakeUplot";
import { isoToLocal } from "../../components/charts/historyData";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { renderTab, twinFixture } from "../../test/twin";
import { HistoryTab } from "./HistoryTab";

vi.mock("uplot", async () => (await import("../../components/charts/fakeUplot")).fakeUplotModule);

function signal(name: string, kind: StreamInfo["signals"][number]["kind"] = "number") {
  return { name, kind, count: 10, first: 1, last: 2 };
}

const STREAMS: StreamInfo[] = [
  { name: "telemetry", count: 20, first: 1, last: 2, signals: [signal("mode", "string"), signal("Cantilever_Angle_radians"), signal("Input_F_in")] },
  { name: "fmu", count: 10, first: 1, last: 2, signals: [signal("theta")] },
];

const DOWNSAMPLE = {
  stream: "telemetry", start: 0, end: 0, points: 2000, skipped: [],
  signals: {
    Cantilever_Angle_radians: { time: [1e18, 1.001e18], value: [0.1, -0.3] },
    Input_F_in: { time: [1e18], value: [2.5] },
  },
};
const AGGREGATE = {
  stream: "telemetry", bucket: "1m", bucket_ns: 60e9, fn: ["max"], skipped: [],
  rows: [{ time: 1e18, values: { Cantilever_Angle_radians: { max: 0.25 }, Input_F_in: { max: 3 } } }],
};

function api(overrides: (url: string) => Response | undefined = () => undefined) {
  return mockFetch((url) => {
    const special = overrides(url);
    if (special) return special;
    if (url.endsWith("/streams")) return jsonResponse({ twin: "tingen", streams: STREAMS });
    if (url.includes("/downsample")) return jsonResponse(DOWNSAMPLE);
    if (url.includes("/aggregate")) return jsonResponse(AGGREGATE);
    if (url.includes("/export")) {
      return new Response("time,x\n", { headers: { "Content-Type": "text/csv", "Content-Disposition": 'attachment; filename="tingen-telemetry.csv"' } });
    }
    return problem(404, "not found");
  });
}

function urls(fetch: ReturnType<typeof api>, part: string): string[] {
  return fetch.mock.calls.map((c) => String(c[0])).filter((u) => u.includes(part));
}

const SIGNALS = "signals=Cantilever_Angle_radians";

// jsdom has no object URLs.
const urlStatics = URL as unknown as Record<string, unknown>;
beforeEach(() => {
  FakeUplot.instances = [];
  setToken("tl_secret");
  urlStatics.createObjectURL = vi.fn(() => "blob:x");
  urlStatics.revokeObjectURL = vi.fn();
});
afterEach(() => {
  vi.unstubAllGlobals();
  delete urlStatics.createObjectURL;
  delete urlStatics.revokeObjectURL;
});

describe("HistoryTab", () => {
  it("plots the min/max downsample of the last hour with a summary", async () => {
    const fetch = api();
    renderTab(<HistoryTab />, twinFixture("viewer"));
    expect(await screen.findByText("points drawn")).toBeInTheDocument();
    expect(urls(fetch, "/downsample")).toEqual([`/api/v1/twins/tingen/streams/telemetry/downsample?points=2000&start=-1h&${SIGNALS}`]);
    expect(screen.getByLabelText("telemetry/mode")).toBeDisabled();
    expect(FakeUplot.instances.at(-1)!.data).toEqual([[1e9, 1.001e9], [0.1, -0.3]]);
    expect(screen.getByText("-0.300000")).toBeInTheDocument();

    fireEvent.click(screen.getByLabelText("telemetry/Input_F_in"));
    await waitFor(() =>
      expect(urls(fetch, "/downsample").at(-1)).toBe(
        "/api/v1/twins/tingen/streams/telemetry/downsample?points=2000&start=-1h&signals=Cantilever_Angle_radians%2CInput_F_in",
      ),
    );
    await waitFor(() => expect(FakeUplot.instances.at(-1)!.opts.series).toHaveLength(3));
    const chart = FakeUplot.instances.at(-1)!;
    expect(chart.opts.series.slice(1).map((s) => s.label)).toEqual(["Cantilever_Angle_radians", "Input_F_in"]);
    expect(chart.data).toEqual([[1e9, 1.001e9], [0.1, -0.3], [2.5, undefined]]);
    // a force of 2.5 N and an angle of 0.3 rad are close enough for one axis
    expect(chart.opts.series.map((s) => s.scale)).toEqual([undefined, "y", "y"]);
  });

  it("draws a signal that sent nothing in the range from its value before, held to the range's end", async () => {
    const start = 1.8e18;
    const fetch = api((url) => {
      if (url.includes("/downsample")) return jsonResponse({ ...DOWNSAMPLE, start, end: null, signals: {} });
      if (url.includes("/latest")) return jsonResponse({ values: { Cantilever_Angle_radians: { time: start - 100e9, value: 0.3 } } });
      return undefined;
    });
    renderTab(<HistoryTab />, twinFixture("viewer", { document: { interface: { signals: [{ name: "Cantilever_Angle_radians", unit: "rad" }] } } }));
    await waitFor(() => expect(FakeUplot.instances.at(-1)?.data).toEqual([[1.8e9], [0.3]]));
    expect(urls(fetch, "/latest")).toEqual([`/api/v1/twins/tingen/streams/telemetry/latest?${SIGNALS}`]);
    const chart = FakeUplot.instances.at(-1)!;
    expect(chart.xRange![0]).toBe(1.8e9);
    expect(chart.xRange![1]).toBeGreaterThanOrEqual(Date.now() / 1000 - 60);
    expect(chart.opts.axes![1]!.label).toBe("rad");
    expect(screen.queryByText(/No samples/)).not.toBeInTheDocument();
  });

  it("aggregates with the auto or a chosen bucket and function, and lists the rows", async () => {
    const fetch = api();
    renderTab(<HistoryTab />, twinFixture("viewer"));
    await screen.findByText("points drawn");
    fireEvent.change(screen.getByLabelText("Mode"), { target: { value: "aggregate" } });
    await screen.findByText("bucket start");
    expect(urls(fetch, "/aggregate")[0]).toBe(`/api/v1/twins/tingen/streams/telemetry/aggregate?bucket=10s&fn=avg&start=-1h&${SIGNALS}`);
    fireEvent.change(screen.getByLabelText("Bucket"), { target: { value: "1m" } });
    fireEvent.change(screen.getByLabelText("Function"), { target: { value: "max" } });
    fireEvent.change(screen.getByLabelText("Range"), { target: { value: "7d" } });
    await waitFor(() =>
      expect(urls(fetch, "/aggregate").at(-1)).toBe(`/api/v1/twins/tingen/streams/telemetry/aggregate?bucket=1m&fn=max&start=-7d&${SIGNALS}`),
    );
    expect(await screen.findByText("max(Cantilever_Angle_radians)")).toBeInTheDocument();
    expect(screen.getByText("0.250000")).toBeInTheDocument();
  });

  it("reads a custom range in local time and zooms into a dragged range", async () => {
    const fetch = api();
    renderTab(<HistoryTab />, twinFixture("viewer"));
    await screen.findByText("points drawn");
    fireEvent.change(screen.getByLabelText("Range"), { target: { value: "custom" } });
    const from = Date.UTC(2026, 10, 21, 10) / 1000;
    fireEvent.change(screen.getByLabelText("From"), { target: { value: isoToLocal(from) } });
    fireEvent.change(screen.getByLabelText("To"), { target: { value: isoToLocal(from + 3600) } });
    await waitFor(() =>
      expect(urls(fetch, "/downsample").at(-1)).toBe(
        `/api/v1/twins/tingen/streams/telemetry/downsample?points=2000&start=2026-11-21T10%3A00%3A00.000Z&end=2026-11-21T11%3A00%3A00.000Z&${SIGNALS}`,
      ),
    );
    act(() => FakeUplot.instances.at(-1)!.drag(from + 60, 60));
    await waitFor(() => expect(urls(fetch, "/downsample").at(-1)).toContain("start=2026-11-21T10%3A01%3A00.000Z&end=2026-11-21T10%3A02%3A00.000Z"));
    fireEvent.change(screen.getByLabelText("To"), { target: { value: isoToLocal(from - 60) } });
    expect(await screen.findByText(/“From” must be before “To”/)).toBeInTheDocument();
  });

  it("downloads the export with the token under the server's file name", async () => {
    const fetch = api();
    const click = vi.spyOn(HTMLAnchorElement.prototype, "click").mockImplementation(() => {});
    renderTab(<HistoryTab />, twinFixture("viewer"));
    await screen.findByText("points drawn");
    fireEvent.click(screen.getByRole("button", { name: "Download CSV" }));
    expect(await screen.findByText("Saved tingen-telemetry.csv")).toBeInTheDocument();
    const [url, init] = fetch.mock.calls.find((c) => String(c[0]).includes("/export"))!;
    expect(url).toBe(`/api/v1/twins/tingen/streams/telemetry/export?format=csv&start=-1h&${SIGNALS}`);
    expect(init?.headers).toMatchObject({ Accept: "text/csv", Authorization: "Bearer tl_secret" });
    expect(click).toHaveBeenCalledTimes(1);
    expect((click.mock.contexts[0] as HTMLAnchorElement).download).toBe("tingen-telemetry.csv");
    click.mockRestore();
  });

  it("names a JSONL download after the twin and stream when the server gives no name", async () => {
    api((url) => (url.includes("/export") ? new Response("{}\n") : undefined));
    const click = vi.spyOn(HTMLAnchorElement.prototype, "click").mockImplementation(() => {});
    renderTab(<HistoryTab />, twinFixture("viewer"));
    await screen.findByText("points drawn");
    fireEvent.click(screen.getByRole("button", { name: "Download JSONL" }));
    expect(await screen.findByText("Saved tingen-telemetry.jsonl")).toBeInTheDocument();
    click.mockRestore();
  });

  it("shows the API's refusal", async () => {
    api((url) => (url.includes("/downsample") ? problem(422, "signal 'mode' holds only text") : undefined));
    renderTab(<HistoryTab />, twinFixture("viewer"));
    expect(await screen.findByRole("alert")).toHaveTextContent("Error (422): signal 'mode' holds only text");
  });

  it("says so when the twin has no data", async () => {
    mockFetch(() => jsonResponse({ twin: "tingen", streams: [] }));
    renderTab(<HistoryTab />, twinFixture("viewer"));
    expect(await screen.findByText(/No data yet/)).toBeInTheDocument();
  });
});
