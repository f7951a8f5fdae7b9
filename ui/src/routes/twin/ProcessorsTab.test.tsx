import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, waitFor, within } from "@testing-library/react";
import { MemoryRouter, Outlet, Route, Routes } from "react-router-dom";
import type { Twin } from "../../api/types";
import { fakeApi, processor } from "../../components/processors/test/api";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import type { TwinContext } from "./context";
import { ProcessorsTab } from "./ProcessorsTab";

afterEach(() => vi.unstubAllGlobals());

const T = "2026-11-21T10:00:00.000Z";
const base = "/api/v1/twins/tingen/processors";
const wait = { timeout: 4000 };

function twin(role: Twin["role"]): Twin {
  return { slug: "tingen", id: "x", name: "Tingen", url: "", created: T, modified: T, levels: ["public"], role, document: {} };
}

function renderTab(role: Twin["role"], path = "/twins/tingen/processors") {
  const context: TwinContext = { slug: "tingen", twin: twin(role), reload: () => {} };
  return render(
    <MemoryRouter initialEntries={[path]} future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <Routes>
        <Route path="/twins/:slug" element={<Outlet context={context} />}>
          <Route path="processors" element={<ProcessorsTab />} />
        </Route>
      </Routes>
    </MemoryRouter>,
  );
}

const crashed = processor({
  name: "crashy",
  blueprint: "fmu",
  output: "sim",
  state: "backoff",
  pid: null,
  last_error: "killed by signal SIGSEGV (Segmentation fault)",
  stats: { ...processor().stats!, restarts: 3, crashes: 3 },
});
const events = [
  { id: 2, time_ns: 1_767_225_660_000_000_000, kind: "crashed", message: "killed by signal SIGSEGV", data: {} },
  { id: 1, time_ns: 1_767_225_600_000_000_000, kind: "started", message: "pid 4242", data: {} },
];
const lines = [
  { time_ns: 1, text: "loading Tingen.fmu" },
  { time_ns: 2, text: "instantiated tingen (CoSimulation)" },
];

function readApi(list = [processor(), crashed]) {
  return fakeApi((url) => {
    if (url === base) return jsonResponse({ processors: list });
    if (url === `${base}/fmu`) return jsonResponse(list[0]);
    if (url.startsWith(`${base}/fmu/events`)) return jsonResponse({ events });
    if (url === `${base}/fmu/logs`) return jsonResponse({ lines });
    return null;
  });
}

describe("ProcessorsTab for viewers", () => {
  it("lists processors with their state, figures and last error, without create or edit buttons", async () => {
    mockFetch(readApi());
    renderTab("viewer");
    const row = await screen.findByTestId("processor-fmu", {}, wait);
    expect(row).toHaveTextContent("telemetry → fmu");
    expect(within(row).getByText("running")).toHaveClass("badge-ok");
    expect(row).toHaveTextContent("1,520");
    expect(row).toHaveTextContent("1,519");
    const bad = screen.getByTestId("processor-crashy");
    expect(bad).toHaveTextContent("telemetry → sim");
    expect(within(bad).getByText("backoff")).toHaveClass("badge-bad");
    expect(bad).toHaveTextContent("killed by signal SIGSEGV");
    expect(bad).toHaveTextContent("3");
    expect(screen.queryByRole("button", { name: "New processor" })).not.toBeInTheDocument();
    expect(await screen.findByRole("table", { name: "Uploaded FMUs" }, wait)).toHaveTextContent("Tingen.fmu");
    expect(screen.queryByRole("form", { name: "Upload an FMU" })).not.toBeInTheDocument();
  });

  it("opens a processor's figures, events and logs read-only", async () => {
    mockFetch(readApi());
    renderTab("viewer");
    fireEvent.click(await screen.findByRole("button", { name: "Details of fmu" }, wait));
    const detail = await screen.findByRole("region", { name: "Processor fmu" });
    const figures = await within(detail).findByLabelText("Status", {}, wait);
    expect(figures).toHaveTextContent("4242");
    expect(figures).toHaveTextContent("45.2 MB");
    expect(figures).toHaveTextContent("12.3 µs / 45.6 µs");
    expect(figures).toHaveTextContent("1.23 ms / 4.20 ms");
    expect(figures).toHaveTextContent("Dropped3");
    expect(within(detail).getByLabelText("Configuration")).toHaveTextContent("F ← Input_F_in");
    const rows = within(await within(detail).findByRole("table", { name: "Events" }, wait)).getAllByRole("row");
    expect(rows[1]).toHaveTextContent("crashed");
    expect(rows[2]).toHaveTextContent("started");
    expect(await within(detail).findByLabelText("Logs", {}, wait)).toHaveTextContent("instantiated tingen (CoSimulation)");
    for (const name of ["Start", "Stop", "Restart", "Delete", "Edit parameters"]) {
      expect(within(detail).queryByRole("button", { name })).not.toBeInTheDocument();
    }
  });

  it("says what went wrong when the list cannot be loaded", async () => {
    mockFetch(fakeApi((url) => (url === base ? problem(403, "reading 'tingen' needs a role on the twin") : null)));
    renderTab("viewer");
    expect(await screen.findByText(/needs a role on the twin/, {}, wait)).toBeInTheDocument();
  });
});

describe("ProcessorsTab for editors", () => {
  it("explains an empty list and offers to create one", async () => {
    mockFetch(readApi([]));
    renderTab("editor");
    expect(await screen.findByText("No processors yet", {}, wait)).toBeInTheDocument();
    fireEvent.click(screen.getByRole("button", { name: "New processor" }));
    expect(await screen.findByRole("form", { name: "New processor" }, wait)).toBeInTheDocument();
  });

  it("stops and deletes a processor, saying what came of it", async () => {
    const fetch = mockFetch((url, init) => {
      if (url === `${base}/fmu/stop`) return jsonResponse(processor({ enabled: false, state: "stopped" }));
      if (url === `${base}/fmu` && init?.method === "DELETE") return new Response(null, { status: 204 });
      return readApi()(url, init);
    });
    vi.stubGlobal("confirm", vi.fn(() => true));
    renderTab("editor", "/twins/tingen/processors?processor=fmu");
    const detail = await screen.findByRole("region", { name: "Processor fmu" }, wait);
    expect(await within(detail).findByRole("button", { name: "Start" }, wait)).toBeDisabled();
    fireEvent.click(within(detail).getByRole("button", { name: "Stop" }));
    expect(await within(detail).findByRole("status", {}, wait)).toHaveTextContent("Stopped: fmu is stopped.");
    expect(fetch.mock.calls.some(([url, init]) => url === `${base}/fmu/stop` && init?.method === "POST")).toBe(true);

    fireEvent.click(within(detail).getByRole("button", { name: "Delete" }));
    expect(window.confirm).toHaveBeenCalled();
    await waitFor(() => expect(screen.queryByRole("region", { name: "Processor fmu" })).not.toBeInTheDocument(), wait);
    expect(screen.getByRole("status")).toHaveTextContent("Deleted fmu.");
    expect(fetch.mock.calls.some(([url, init]) => url === `${base}/fmu` && init?.method === "DELETE")).toBe(true);
  });

  it("changes the parameters with the generated form and tells whether the state was kept", async () => {
    const fetch = mockFetch((url, init) => {
      if (url === `${base}/fmu` && init?.method === "PATCH") return jsonResponse({ ...processor(), kept_state: true });
      return readApi()(url, init);
    });
    renderTab("editor", "/twins/tingen/processors?processor=fmu");
    fireEvent.click(await screen.findByRole("button", { name: "Edit parameters" }, wait));
    const form = await screen.findByRole("form", { name: "Parameters of fmu" }, wait);
    const level = await within(form).findByLabelText("Log Level", {}, wait);
    fireEvent.change(level, { target: { value: "2" } }); // all
    fireEvent.click(within(form).getByRole("button", { name: "Save parameters" }));
    expect(await within(form).findByRole("status", {}, wait)).toHaveTextContent("Parameters saved: state kept (running).");
    const patch = fetch.mock.calls.find(([, init]) => init?.method === "PATCH")!;
    expect(JSON.parse(String(patch[1]?.body))).toEqual({ params: { fmu: "Tingen.fmu", outputs: ["theta", "sigma"], log_level: "all" } });
  });
});

describe("ProcessorsTab polling", () => {
  it("loads the list again every few seconds and stops when it is left", async () => {
    vi.useFakeTimers({ shouldAdvanceTime: true });
    try {
      const fetch = mockFetch(readApi());
      const view = renderTab("viewer");
      await screen.findByTestId("processor-fmu", {}, wait);
      const lists = () => fetch.mock.calls.filter(([url]) => url === base).length;
      const before = lists();
      await vi.advanceTimersByTimeAsync(3100);
      await waitFor(() => expect(lists()).toBe(before + 1));
      view.unmount();
      await vi.advanceTimersByTimeAsync(10_000);
      expect(lists()).toBe(before + 1);
    } finally {
      vi.useRealTimers();
    }
  });
});
