import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { act, fireEvent, render, screen, waitFor } from "@testing-library/react";
import { MemoryRouter, Outlet, Route, Routes, useLocation } from "react-router-dom";
import { setToken } from "../../api/client";
import type { StreamInfo } from "../../api/history";
import { FakeUplot } from "../../components/charts/fakeUplot";
import { FakeSocket } from "../../live/fakeSocket";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { twinFixture } from "../../test/twin";
import type { TwinContext } from "./context";
import { LiveTab } from "./LiveTab";

vi.mock("uplot", async () => (await import("../../components/charts/fakeUplot")).fakeUplotModule);

function signal(name: string, kind: StreamInfo["signals"][number]["kind"] = "number") {
  return { name, kind, count: 10, first: 1, last: 2 };
}

const STREAMS: StreamInfo[] = [
  { name: "telemetry", count: 20, first: 1, last: 2, signals: [signal("Cantilever_Angle_radians"), signal("Input_F_in"), signal("mode", "string")] },
  { name: "fmu", count: 10, first: 1, last: 2, signals: [signal("sigma"), signal("theta")] },
];

const NOW_NS = Date.now() * 1e6;

function downsampleAnswer(url: string) {
  const names = new URL(url, "http://x").searchParams.get("signals")!.split(",");
  const signals = Object.fromEntries(names.map((n) => [n, { time: [NOW_NS - 2e9, NOW_NS - 1e9], value: [0.1, 0.2] }]));
  return jsonResponse({ stream: "s", start: 0, end: 0, points: 100, skipped: [], signals });
}

function api(streams: StreamInfo[] | Response, latest: Record<string, { time: number; value: unknown }> = {}) {
  return mockFetch((url) => {
    if (url.endsWith("/streams")) return streams instanceof Response ? streams : jsonResponse({ twin: "tingen", streams });
    if (url.includes("/downsample")) return downsampleAnswer(url);
    if (url.includes("/latest")) return jsonResponse({ twin: "tingen", stream: "s", values: latest });
    return problem(404, "not found");
  });
}

let location = "";
function ShowLocation() {
  const here = useLocation();
  location = here.pathname + here.search;
  return null;
}

function renderLive(path = "/twins/tingen/live") {
  const context: TwinContext = { slug: "tingen", twin: twinFixture("viewer"), reload: () => {} };
  return render(
    <MemoryRouter initialEntries={[path]} future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <ShowLocation />
      <Routes>
        <Route path="/twins/:slug" element={<Outlet context={context} />}>
          <Route path="live" element={<LiveTab />} />
        </Route>
      </Routes>
    </MemoryRouter>,
  );
}

async function connected(): Promise<FakeSocket> {
  await waitFor(() => expect(FakeSocket.instances.length).toBeGreaterThan(0));
  const socket = FakeSocket.latest();
  act(() => {
    socket.open();
    socket.welcome(NOW_NS);
  });
  return socket;
}

function samples(socket: FakeSocket, sub: string, stream: string, count: number, scale = 1e-3) {
  const rows = Array.from({ length: count }, (_, i) => ({
    time: NOW_NS - (count - i) * 1e6,
    values: { Cantilever_Angle_radians: i * scale, theta: -i * scale },
  }));
  act(() => socket.receive({ type: "samples", sub, twin: "tingen", stream, received: NOW_NS + 5e6, sent: NOW_NS + 6e6, samples: rows }));
}

beforeEach(() => {
  FakeSocket.instances = [];
  FakeUplot.instances = [];
  vi.stubGlobal("WebSocket", FakeSocket);
  setToken("tl_secret");
});
afterEach(() => vi.unstubAllGlobals());

describe("LiveTab", () => {
  it("offers the numeric signals grouped by stream, the demo's two angles chosen", async () => {
    api(STREAMS);
    renderLive();
    expect(await screen.findByRole("group", { name: "telemetry" })).toBeInTheDocument();
    expect(screen.getByRole("group", { name: "fmu" })).toBeInTheDocument();
    expect(screen.getByLabelText("telemetry/Cantilever_Angle_radians")).toBeChecked();
    expect(screen.getByLabelText("fmu/theta")).toBeChecked();
    expect(screen.getByLabelText("telemetry/Input_F_in")).not.toBeChecked();
    expect(screen.getByLabelText("telemetry/mode")).toBeDisabled();

    fireEvent.click(screen.getByLabelText("telemetry/Input_F_in"));
    expect(location).toBe(`/twins/tingen/live?s=${encodeURIComponent("telemetry:Cantilever_Angle_radians,fmu:theta,telemetry:Input_F_in")}`);
    expect(screen.getByLabelText("telemetry/Input_F_in")).toBeChecked();
  });

  it("subscribes per stream, counts the points, unsubscribes while paused and subscribes again on resume", async () => {
    const fetch = api(STREAMS);
    renderLive();
    const socket = await connected();
    expect(socket.sent[0]).toEqual({ op: "auth", token: "tl_secret" });
    expect(socket.ops("subscribe")).toEqual([
      { op: "subscribe", id: "s1", twin: "tingen", stream: "telemetry", signals: ["Cantilever_Angle_radians"] },
      { op: "subscribe", id: "s2", twin: "tingen", stream: "fmu", signals: ["theta"] },
    ]);
    const backfills = fetch.mock.calls.map((c) => String(c[0])).filter((u) => u.includes("/downsample"));
    expect(backfills).toContain("/api/v1/twins/tingen/streams/telemetry/downsample?points=1600&start=-30s&signals=Cantilever_Angle_radians");
    expect(await screen.findByText("connected")).toBeInTheDocument();

    samples(socket, "s1", "telemetry", 500);
    samples(socket, "s2", "fmu", 100);
    await waitFor(() => expect(screen.getByTestId("live-points")).toHaveTextContent(/^600$/));
    expect(screen.getByTestId("stats-telemetry")).toHaveTextContent(/delay 2\d\d ms \(p99 4\d\d ms\)/);
    expect(screen.getByTestId("stats-telemetry")).toHaveTextContent("platform 1.0 ms");

    fireEvent.click(screen.getByRole("button", { name: "Pause" }));
    expect(screen.getByText("Paused: not receiving")).toBeInTheDocument();
    expect(socket.ops("unsubscribe").map((m) => m.id)).toEqual(["s1", "s2"]);
    samples(socket, "s1", "telemetry", 50); // in flight before the unsubscribe: not counted
    await new Promise((r) => setTimeout(r, 300));
    expect(screen.getByTestId("live-points")).toHaveTextContent(/^600$/);

    fireEvent.click(screen.getByRole("button", { name: "Resume" }));
    expect(socket.ops("subscribe").map((m) => m.id)).toEqual(["s1", "s2", "s3", "s4"]);
    samples(socket, "s3", "telemetry", 10);
    await waitFor(() => expect(screen.getByTestId("live-points")).toHaveTextContent(/^610$/));
    expect(screen.queryByText("Paused: not receiving")).not.toBeInTheDocument();
  });

  it("draws the chosen signals on one chart", async () => {
    api(STREAMS);
    renderLive();
    const socket = await connected();
    samples(socket, "s1", "telemetry", 100);
    await waitFor(() => expect(FakeUplot.instances.at(-1)?.xRange).not.toBeNull());
    const chart = FakeUplot.instances.at(-1)!;
    expect(chart.opts.series.slice(1).map((s) => s.label)).toEqual(["telemetry/Cantilever_Angle_radians", "fmu/theta"]);
    const [x0, x1] = chart.xRange!;
    expect(x1 - x0).toBe(30);
    expect((chart.data[1] as (number | null)[]).some((v) => v !== null)).toBe(true);

    // dragging zooms and stops following; "Follow live" follows again
    act(() => chart.drag(x0 + 5, 10));
    await waitFor(() => expect(chart.xRange).toEqual([x0 + 5, x0 + 15]));
    fireEvent.click(screen.getByRole("button", { name: "Follow live" }));
    await waitFor(() => expect(chart.xRange![1] - chart.xRange![0]).toBe(30));
    expect(screen.queryByRole("button", { name: "Follow live" })).not.toBeInTheDocument();
  });

  it("holds a signal sent on change to now, from its one sample long before the window", async () => {
    // The crane stood still for ten minutes: no sample in the window, none arriving.
    mockFetch((url) => {
      if (url.endsWith("/streams")) return jsonResponse({ twin: "tingen", streams: STREAMS });
      if (url.includes("/downsample")) return jsonResponse({ stream: "telemetry", start: 0, end: 0, points: 100, skipped: [], signals: {} });
      if (url.includes("/latest")) return jsonResponse({ values: { Input_F_in: { time: NOW_NS - 600e9, value: 4.5 } } });
      return problem(404, "not found");
    });
    const context: TwinContext = {
      slug: "tingen",
      twin: twinFixture("viewer", { document: { interface: { signals: [{ name: "Input_F_in", unit: "N" }] } } }),
      reload: () => {},
    };
    render(
      <MemoryRouter initialEntries={["/twins/tingen/live?s=telemetry:Input_F_in"]} future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
        <Routes>
          <Route path="/twins/:slug" element={<Outlet context={context} />}>
            <Route path="live" element={<LiveTab />} />
          </Route>
        </Routes>
      </MemoryRouter>,
    );
    await connected();
    await waitFor(() => expect(FakeUplot.instances.at(-1)?.data[1]).toContain(4.5));
    const chart = FakeUplot.instances.at(-1)!;
    const [start, end] = chart.xRange!;
    expect(chart.data).toEqual([[start], [4.5]]);
    // ...and the draw hook holds it, dashed, from the window's start to its end (now)
    const held = vi.fn();
    const ctx = { save: vi.fn(), restore: vi.fn(), beginPath: vi.fn(), rect: vi.fn(), clip: vi.fn(), setLineDash: vi.fn(), moveTo: held, lineTo: held, stroke: vi.fn() };
    const drawn = Object.assign(chart, { ctx, series: [{}, { show: true, scale: "y" }], valToPos: (v: number) => v });
    chart.opts.hooks!.draw![0]!(drawn as never);
    expect(held.mock.calls).toEqual([
      [start, 4.5],
      [end, 4.5],
    ]);
    expect(chart.opts.axes![1]!.label).toBe("N");
  });

  it("puts signals of very different sizes on a second axis", async () => {
    api(STREAMS);
    renderLive();
    const socket = await connected();
    samples(socket, "s2", "fmu", 100, 1e6); // theta in the millions beside an angle of 0.2
    await waitFor(() => expect(FakeUplot.instances.at(-1)?.opts.series[2]?.scale).toBe("y2"), { timeout: 3000 });
    const chart = FakeUplot.instances.at(-1)!;
    expect(chart.opts.series[1]?.scale).toBe("y");
    expect(chart.opts.axes?.map((a) => a.scale)).toEqual([undefined, "y", "y2"]);
  });

  it("takes the signals and the window from the URL", async () => {
    const fetch = api(STREAMS);
    renderLive("/twins/tingen/live?s=telemetry:Input_F_in,gone:x&w=900");
    const socket = await connected();
    expect(screen.getByLabelText("telemetry/Input_F_in")).toBeChecked();
    expect(screen.getByLabelText("telemetry/Cantilever_Angle_radians")).not.toBeChecked();
    expect(screen.getByLabelText("Window")).toHaveValue("900");
    const rate = Math.floor((1 << 20) / 900);
    expect(socket.ops("subscribe")).toEqual([
      { op: "subscribe", id: "s1", twin: "tingen", stream: "telemetry", signals: ["Input_F_in"], max_rate: rate },
    ]);
    expect(screen.getByText(/thinned to at most 1,165 samples\/s/)).toBeInTheDocument();
    expect(fetch.mock.calls.map((c) => String(c[0]))).toContain(
      "/api/v1/twins/tingen/streams/telemetry/downsample?points=1600&start=-900s&signals=Input_F_in",
    );
    fireEvent.change(screen.getByLabelText("Window"), { target: { value: "10" } });
    expect(location).toContain("w=10");
  });

  it("says so when the twin has no data yet", async () => {
    api([]);
    renderLive();
    expect(await screen.findByText(/No data yet: connect a device/)).toBeInTheDocument();
    expect(FakeSocket.instances).toHaveLength(0);
  });

  it("says so when no signal is numeric", async () => {
    api([{ name: "log", count: 1, first: 1, last: 1, signals: [signal("line", "string")] }]);
    renderLive();
    expect(await screen.findByText(/no numeric signals/)).toBeInTheDocument();
  });

  it("shows API errors and a refused live connection", async () => {
    api(problem(404, "no twin 'tingen'"));
    renderLive();
    expect(await screen.findByRole("alert")).toHaveTextContent("no twin 'tingen'");
  });

  it("stops with a clear message when the token is refused", async () => {
    api(STREAMS);
    renderLive();
    await waitFor(() => expect(FakeSocket.instances.length).toBe(1));
    act(() => FakeSocket.latest().drop(4401, "token revoked"));
    expect(await screen.findByRole("alert")).toHaveTextContent("The live connection was refused: token revoked. Sign in again");
  });

  it("shows a refused subscription and a reconnecting connection", async () => {
    api(STREAMS);
    renderLive();
    const socket = await connected();
    act(() => socket.receive({ type: "error", op: "subscribe", id: "s2", message: "no stream 'fmu'" }));
    expect(await screen.findByRole("alert")).toHaveTextContent("fmu: no stream 'fmu'");
    act(() => socket.drop(1006));
    expect(await screen.findByText(/reconnecting in \d s/)).toBeInTheDocument();
  });
});
