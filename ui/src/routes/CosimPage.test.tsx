import { afterEach, describe, expect, it, vi } from "vitest";
import { render, screen, waitFor, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { MemoryRouter, Route, Routes } from "react-router-dom";
import { setToken } from "../api/client";
import { FakeUplot } from "../components/charts/fakeUplot";
import { jsonResponse, mockFetch, problem } from "../test/fetch";
import { CosimPage, RUNNING_REFRESH_MS } from "./CosimPage";

vi.mock("uplot", async () => (await import("../components/charts/fakeUplot")).fakeUplotModule);

afterEach(() => {
  vi.unstubAllGlobals();
  vi.restoreAllMocks();
  FakeUplot.instances = [];
});

const system = (loops: string[][] = []) => ({
  source: "maestro",
  instances: [
    { name: "msd1.m1", fmu: "msd_mass.fmu", kind: "co-simulation", isolated: false },
    { name: "msd2.m2", fmu: "msd_spring.fmu", kind: "model-exchange", isolated: true },
  ],
  connections: [
    { source: "msd1.m1.x1", target: "msd2.m2.x1" },
    { source: "msd1.m1.v1", target: "msd2.m2.v1" },
    { source: "msd2.m2.fk", target: "msd1.m1.fk" },
  ],
  algorithm: { kind: "fixed-step", size: 0.001, min_size: null, max_size: null, master: "jacobi" },
  start_time: 0,
  end_time: 10,
  loops,
});
const cosim = (state: string, progress: number, extra: Record<string, unknown> = {}) => ({
  id: 3, name: "msd", owner: "ann", twin: "rig", prefix: "sim.", mode: "batch", factor: 1, state, progress, sim_time: progress * 10,
  message: "", created_at: 1.7e18, started_at: state === "created" ? null : 1.7e18, ended_at: null, system: system(),
  columns: ["time", "msd1.m1.x1", "msd2.m2.fk"], rows: 3, ...extra,
});
const results = (n: number) => ({
  columns: ["time", "msd1.m1.x1", "msd2.m2.fk"],
  data: [Array.from({ length: n }, (_, i) => i * 0.1), Array.from({ length: n }, () => 1), Array.from({ length: n }, () => -2)],
});

function renderPage(impl: (url: string, init?: RequestInit) => Response, state: unknown = null) {
  setToken("tl_x");
  const fetch = mockFetch(impl);
  render(
    <MemoryRouter initialEntries={[{ pathname: "/cosims/3", state }]} future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <Routes>
        <Route path="/cosims" element={<p>the list</p>} />
        <Route path="/cosims/:id" element={<CosimPage />} />
      </Routes>
    </MemoryRouter>,
  );
  return fetch;
}

const calls = (fetch: ReturnType<typeof mockFetch>, url: string, method = "GET") =>
  fetch.mock.calls.filter(([u, init]) => String(u).split("?")[0] === url && (init?.method ?? "GET") === method);

describe("CosimPage", () => {
  it("shows a running co-simulation's progress, its results chart and its connection graph", async () => {
    renderPage((url) => {
      if (url === "/api/v1/cosims/3") return jsonResponse(cosim("running", 0.25));
      if (url.startsWith("/api/v1/cosims/3/results?")) return jsonResponse(results(5));
      return problem(404, url);
    });
    expect(await screen.findByRole("heading", { name: /msd/, level: 1 })).toHaveTextContent("running");
    expect(screen.getByRole("progressbar", { name: "Progress" })).toHaveAttribute("value", "0.25");
    expect(screen.getByText(/25%.*t = 2\.5 s of 10 s/)).toBeInTheDocument();
    expect(screen.getByRole("button", { name: "Stop" })).toBeInTheDocument();
    expect(screen.queryByRole("button", { name: "Delete" })).toBeNull();
    // The chart: one series per column after the time, the server's points as they are.
    await waitFor(() => expect(FakeUplot.instances).toHaveLength(1));
    const chart = FakeUplot.instances[0]!;
    expect(chart.opts.series.map((s) => s.label)).toEqual(["time (s)", "msd1.m1.x1", "msd2.m2.fk"]);
    expect(chart.data[0]).toHaveLength(5);
    expect(screen.getByRole("figure", { name: "Results: 2 columns, 5 points" })).toBeInTheDocument();
    // The graph: both instances, the pair's arrows labelled; no loop.
    const graph = screen.getByRole("img", { name: "Connection graph: 2 instances, 3 connections" });
    expect(within(graph).getByText("msd1.m1")).toBeInTheDocument();
    expect(within(graph).getByText("x1, v1")).toBeInTheDocument();
    expect(within(graph).getByText("ME isolated")).toBeInTheDocument();
    expect(screen.getByText("No algebraic loop.")).toBeInTheDocument();
    expect(screen.getByRole("link", { name: "rig" })).toHaveAttribute("href", "/twins/rig/history");
  });

  it("reads the state and the results again while it runs, and stops once it has ended", async () => {
    vi.useFakeTimers({ shouldAdvanceTime: true });
    try {
      let state = "running";
      const fetch = renderPage((url) => {
        if (url === "/api/v1/cosims/3") return jsonResponse(cosim(state, state === "running" ? 0.5 : 1));
        if (url.startsWith("/api/v1/cosims/3/results?")) return jsonResponse(results(state === "running" ? 5 : 101));
        return problem(404, url);
      });
      await screen.findByRole("button", { name: "Stop" });
      const views = () => calls(fetch, "/api/v1/cosims/3").length;
      const before = views();
      await vi.advanceTimersByTimeAsync(RUNNING_REFRESH_MS + 50);
      await waitFor(() => expect(views()).toBe(before + 1));
      state = "finished";
      await vi.advanceTimersByTimeAsync(RUNNING_REFRESH_MS + 50);
      expect(await screen.findByRole("button", { name: "Start again" })).toBeInTheDocument();
      // The ended run's results are read once more, whole.
      await waitFor(() => expect(FakeUplot.instances.at(-1)!.data[0]).toHaveLength(101));
      const ended = views();
      const resultsRead = calls(fetch, "/api/v1/cosims/3/results").length;
      await vi.advanceTimersByTimeAsync(10_000);
      expect(views()).toBe(ended);
      expect(calls(fetch, "/api/v1/cosims/3/results")).toHaveLength(resultsRead);
      expect(calls(fetch, "/api/v1/cosims/3/results")[0]![0]).toContain("max_points=2000");
    } finally {
      vi.useRealTimers();
    }
  });

  it("stops a run, and starts an ended one again in the mode chosen", async () => {
    let state = "running";
    const fetch = renderPage((url) => {
      if (url === "/api/v1/cosims/3/stop") state = "stopped";
      if (url === "/api/v1/cosims/3/start") state = "running";
      if (url.startsWith("/api/v1/cosims/3/results?")) return jsonResponse(results(3));
      if (url.startsWith("/api/v1/cosims/3")) return jsonResponse(cosim(state, 0.3));
      return problem(404, url);
    });
    await userEvent.click(await screen.findByRole("button", { name: "Stop" }));
    await userEvent.selectOptions(await screen.findByLabelText("Mode"), "realtime");
    await userEvent.clear(screen.getByLabelText("Speed factor"));
    await userEvent.type(screen.getByLabelText("Speed factor"), "0");
    await userEvent.click(screen.getByRole("button", { name: "Start again" }));
    expect(screen.getByRole("alert")).toHaveTextContent("The speed factor is a number above 0");
    expect(calls(fetch, "/api/v1/cosims/3/start", "POST")).toHaveLength(0);
    await userEvent.clear(screen.getByLabelText("Speed factor"));
    await userEvent.type(screen.getByLabelText("Speed factor"), "2.5");
    await userEvent.click(screen.getByRole("button", { name: "Start again" }));
    await screen.findByRole("button", { name: "Stop" });
    const [start] = calls(fetch, "/api/v1/cosims/3/start", "POST");
    expect(JSON.parse(String(start![1]?.body))).toEqual({ mode: "realtime", factor: 2.5 });
    expect(calls(fetch, "/api/v1/cosims/3/stop", "POST")).toHaveLength(1);
  });

  it("downloads the CSV with the token, and deletes an ended run after asking", async () => {
    const created = vi.fn(() => "blob:csv");
    vi.stubGlobal("URL", Object.assign(URL, { createObjectURL: created, revokeObjectURL: vi.fn() }));
    const click = vi.spyOn(HTMLAnchorElement.prototype, "click").mockImplementation(() => undefined);
    vi.spyOn(window, "confirm").mockReturnValue(true);
    const fetch = renderPage((url, init) => {
      if (url === "/api/v1/cosims/3/results.csv") return new Response("time,{msd1}.m1.x1\n0,1\n", { headers: { "Content-Type": "text/csv" } });
      if (url.startsWith("/api/v1/cosims/3/results?")) return jsonResponse(results(3));
      if (url === "/api/v1/cosims/3" && init?.method === "DELETE") return new Response(null, { status: 204 });
      if (url === "/api/v1/cosims/3") return jsonResponse(cosim("finished", 1));
      return problem(404, url);
    });
    await userEvent.click(await screen.findByRole("button", { name: "Download CSV" }));
    await waitFor(() => expect(click).toHaveBeenCalled());
    const [csv] = calls(fetch, "/api/v1/cosims/3/results.csv");
    expect((csv![1]?.headers as Record<string, string>).Authorization).toBe("Bearer tl_x");
    expect((click.mock.contexts[0] as HTMLAnchorElement).download).toBe("msd-outputs.csv");
    await userEvent.click(screen.getByRole("button", { name: "Delete" }));
    expect(await screen.findByText("the list")).toBeInTheDocument();
    expect(calls(fetch, "/api/v1/cosims/3", "DELETE")).toHaveLength(1);
  });

  it("reads no results before the first start, and names an algebraic loop", async () => {
    const fetch = renderPage((url) => {
      if (url === "/api/v1/cosims/3") {
        return jsonResponse(cosim("created", 0, { message: "", system: system([["msd1.m1.x1", "msd2.m2.x1", "msd2.m2.fk", "msd1.m1.fk"]]) }));
      }
      return problem(404, url);
    });
    expect(await screen.findByText("No results yet: choose “Start”.")).toBeInTheDocument();
    expect(screen.getByRole("button", { name: "Download CSV" })).toBeDisabled();
    expect(calls(fetch, "/api/v1/cosims/3/results")).toHaveLength(0);
    const note = screen.getByRole("note");
    expect(note).toHaveTextContent("An algebraic loop");
    expect(within(note).getByText("msd1.m1.x1 → msd2.m2.x1 → msd2.m2.fk → msd1.m1.fk → msd1.m1.x1")).toBeInTheDocument();
    const graph = screen.getByRole("img");
    expect(graph.querySelectorAll(".cosim-box.cosim-loop")).toHaveLength(2);
    // x1 feeds the loop, v1 does not: one arrow each way, both in it.
    expect(graph.querySelectorAll(".cosim-edge.cosim-loop")).toHaveLength(2);
  });

  it("says once why the page that made it could not start it", async () => {
    renderPage((url) => (url === "/api/v1/cosims/3" ? jsonResponse(cosim("created", 0)) : problem(404, url)), { startError: "the system has algebraic loops" });
    expect(await screen.findByRole("alert")).toHaveTextContent("Made, but not started: the system has algebraic loops");
  });

  it("says why a run failed", async () => {
    renderPage((url) => {
      if (url === "/api/v1/cosims/3") return jsonResponse(cosim("failed", 0.4, { message: "msd2.m2: fmi2DoStep failed at t = 4" }));
      if (url.startsWith("/api/v1/cosims/3/results?")) return jsonResponse({ columns: ["time"], data: [[]] });
      return problem(404, url);
    });
    expect(await screen.findByRole("alert")).toHaveTextContent("msd2.m2: fmi2DoStep failed at t = 4");
    expect(await screen.findByText("This run wrote no rows.")).toBeInTheDocument();
  });
});
