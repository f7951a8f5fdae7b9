import { afterEach, describe, expect, it, vi } from "vitest";
import { act, render, screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { MemoryRouter, Route, Routes, useLocation } from "react-router-dom";
import { setToken } from "../api/client";
import { jsonResponse, mockFetch, problem } from "../test/fetch";
import { DeploymentPage, transitionsOf } from "./DeploymentPage";
import { RECONNECT_MS } from "../components/deployments/RunLog";

afterEach(() => {
  vi.unstubAllGlobals();
  vi.restoreAllMocks();
});

/** A WebSocket the test speaks for: what the page sent, and frames pushed to it. */
class FakeSocket {
  static all: FakeSocket[] = [];
  sent: string[] = [];
  closed = false;
  onopen: (() => void) | null = null;
  onmessage: ((e: { data: unknown }) => void) | null = null;
  onclose: ((e: { code: number; reason: string }) => void) | null = null;
  constructor(readonly url: string) {
    FakeSocket.all.push(this);
  }
  send(data: string) {
    this.sent.push(data);
  }
  close() {
    this.closed = true;
  }
  open() {
    act(() => this.onopen?.());
  }
  /** A log chunk: a binary frame. */
  push(bytes: Uint8Array) {
    const data = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
    act(() => this.onmessage?.({ data }));
  }
  /** The end: a text frame. */
  pushText(data: string) {
    act(() => this.onmessage?.({ data }));
  }
  end(code = 1000, reason = "") {
    act(() => this.onclose?.({ code, reason }));
  }
}

const deployment = (state: string) => ({
  id: "d1", name: "rig-a", package: `lib:common/twins/tingen-rig@sha256:${"a".repeat(64)}`, package_ref: "tingen-rig@1.0.0",
  parameters: { zeta: 0.9 }, state, twin: "rig-a", resources: { twin: "rig-a", devices: ["tingenSAP"], processors: ["fmu"], connectors: [], services: [] },
  created_by: "admin", created_ns: 1.7e18, updated_ns: 1.7e18, error: null,
});
const run = (id: number, phase: string, state: string, exit_code: number | null) => ({
  id, deployment: "rig-a", phase, state, exit_code, started_by: "admin", created_ns: 1.7e18, started_ns: 1.7e18, ended_ns: state === "running" ? null : 1.7e18, node: "n1", error: null,
});

/** The history entry's state, shown for the test to read. */
function HistoryState() {
  return <div data-testid="history-state">{JSON.stringify(useLocation().state)}</div>;
}

function setup(historyState: unknown = null) {
  setToken("tl_x");
  FakeSocket.all = [];
  vi.stubGlobal("WebSocket", FakeSocket);
  let state = "running";
  const fetch = mockFetch((url, init) => {
    if (url === "/api/v1/deployments/rig-a") return jsonResponse(deployment(state));
    if (url === "/api/v1/deployments/rig-a/runs" && init?.method === "POST") return problem(403, "only admins may start runs (script_runners is admins)");
    if (url === "/api/v1/deployments/rig-a/runs") return jsonResponse({ runs: [run(2, "execute", "running", null), run(1, "analyze", "failed", 3)] });
    if (url === "/api/v1/deployments/rig-a/stop" && init?.method === "POST") {
      state = "stopped";
      return jsonResponse(deployment(state));
    }
    if (url === "/api/v1/runs/1/log?offset=0") return new Response("reading history\nno samples\n", { headers: { "X-Run-State": "failed" } });
    if (url === "/api/v1/runs/2/log?offset=0") return new Response("started\nstep 1: 2.5 m³\nstep 2\n", { headers: { "X-Run-State": "succeeded" } });
    return problem(404, `unexpected ${url}`);
  });
  render(
    <MemoryRouter initialEntries={[{ pathname: "/deployments/rig-a", state: historyState }]} future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <Routes>
        <Route
          path="/deployments/:name"
          element={
            <>
              <DeploymentPage />
              <HistoryState />
            </>
          }
        />
      </Routes>
    </MemoryRouter>,
  );
  return fetch;
}

describe("DeploymentPage", () => {
  it("follows the active run's log over its WebSocket, the token in the first message", async () => {
    setup();
    const runs = await screen.findByRole("table", { name: "Runs" });
    expect(within(runs).getAllByRole("row")).toHaveLength(3);
    await vi.waitFor(() => expect(FakeSocket.all).toHaveLength(1));
    const socket = FakeSocket.all[0]!;
    expect(socket.url).toBe("ws://localhost:3000/api/v1/runs/2/log/ws");
    socket.open();
    expect(socket.sent).toEqual([JSON.stringify({ op: "auth", token: "tl_x" })]);
    // "m³" is cut between two chunks inside the "³" (two bytes in UTF-8): read whole.
    const bytes = new TextEncoder().encode("started\nstep 1: 2.5 m³\n");
    const cut = bytes.length - 2;
    socket.push(bytes.subarray(0, cut));
    const log = screen.getByTestId("run-log");
    expect(log).toHaveTextContent("started step 1: 2.5 m");
    socket.push(bytes.subarray(cut));
    expect(log.textContent).toBe("started\nstep 1: 2.5 m³\n");
    socket.pushText('{"state": "succeeded", "exit_code": 0}');
    expect(screen.getByRole("region", { name: "Log of run 2" })).toHaveTextContent("succeeded exit code 0");
    socket.end();
    // Once the socket is done, the stored log is the text shown: all of it.
    await vi.waitFor(() => expect(log.textContent).toBe("started\nstep 1: 2.5 m³\nstep 2\n"));
  });

  it("follows again from the byte it had reached when the socket drops while the run goes on", async () => {
    setup();
    await vi.waitFor(() => expect(FakeSocket.all).toHaveLength(1));
    const first = FakeSocket.all[0]!;
    first.open();
    first.push(new TextEncoder().encode("started\n"));
    first.end(1006);
    await vi.waitFor(() => expect(FakeSocket.all).toHaveLength(2), { timeout: 5000 });
    const second = FakeSocket.all[1]!;
    expect(second.url).toBe("ws://localhost:3000/api/v1/runs/2/log/ws?offset=8");
    second.open();
    expect(second.sent).toEqual([JSON.stringify({ op: "auth", token: "tl_x" })]);
    second.push(new TextEncoder().encode("step 1\n"));
    expect(screen.getByTestId("run-log").textContent).toBe("started\nstep 1\n");
  });

  it("does not follow again a log the server refused, and says why", async () => {
    const timers = vi.spyOn(globalThis, "setTimeout");
    setup();
    await vi.waitFor(() => expect(FakeSocket.all).toHaveLength(1));
    FakeSocket.all[0]!.end(4401, "the token is not valid");
    expect(await screen.findByRole("alert")).toHaveTextContent("The live log ended: the token is not valid");
    // No second try is even planned (a dropped socket plans one RECONNECT_MS later).
    expect(timers.mock.calls.some(([, ms]) => ms === RECONNECT_MS)).toBe(false);
    FakeSocket.all[0]!.end(1006);
    expect(timers.mock.calls.some(([, ms]) => ms === RECONNECT_MS)).toBe(true);
  });

  it("reads a finished run's whole log when it is opened", async () => {
    setup();
    const runs = await screen.findByRole("table", { name: "Runs" });
    await userEvent.click(within(runs).getByRole("button", { name: "Log of analyze run 1" }));
    const shown = await screen.findByRole("region", { name: "Log of run 1" });
    await vi.waitFor(() => expect(within(shown).getByTestId("run-log")).toHaveTextContent("reading history no samples"));
    expect(shown).toHaveTextContent("failed exit code 3");
  });

  it("stops a running deployment, and shows why a run was refused", async () => {
    const fetch = setup();
    await userEvent.click(await screen.findByRole("button", { name: "Stop" }));
    expect(await screen.findByRole("button", { name: "Start" })).toBeInTheDocument();
    expect(fetch.mock.calls.some(([u, i]) => String(u) === "/api/v1/deployments/rig-a/stop" && i?.method === "POST")).toBe(true);
    await userEvent.selectOptions(screen.getByLabelText("Run phase"), "evolve");
    await userEvent.click(screen.getByRole("button", { name: "Run" }));
    expect(await screen.findByRole("alert")).toHaveTextContent("(403): only admins may start runs");
    const sent = fetch.mock.calls.find(([u, i]) => String(u) === "/api/v1/deployments/rig-a/runs" && i?.method === "POST");
    expect(JSON.parse(String(sent![1]!.body))).toEqual({ phase: "evolve" });
  });

  it("shows the device tokens handed over by the deploy, once: not in the history entry after", async () => {
    setup({ deviceTokens: { level: "tld_secret" } });
    expect(await screen.findByRole("status")).toHaveTextContent("level: tld_secret");
    // Shown still after the page took the tokens out of its history entry.
    await vi.waitFor(() => expect(screen.getByTestId("history-state")).toHaveTextContent("null"));
    expect(screen.getByRole("status")).toHaveTextContent("level: tld_secret");
  });

  it("offers the transitions each state allows", () => {
    expect(transitionsOf("planned")).toEqual(["create", "terminate"]);
    expect(transitionsOf("created")).toEqual(["start", "terminate"]);
    expect(transitionsOf("running")).toEqual(["stop", "terminate"]);
    expect(transitionsOf("stopped")).toEqual(["start", "terminate"]);
    expect(transitionsOf("terminated")).toEqual([]);
    expect(transitionsOf("failed")).toEqual([]);
  });
});
