import { afterEach, describe, expect, it, vi } from "vitest";
import { render, screen, waitFor, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { MemoryRouter, Route, Routes, useLocation, useParams } from "react-router-dom";
import { setToken } from "../api/client";
import { jsonResponse, mockFetch, problem } from "../test/fetch";
import { CosimsPage } from "./CosimsPage";
import { contentTypeOf, nameFromFile } from "../api/cosims";

afterEach(() => vi.unstubAllGlobals());

const system = {
  source: "maestro",
  instances: [
    { name: "msd1.m1", fmu: "msd_mass.fmu", kind: "co-simulation", isolated: false },
    { name: "msd2.m2", fmu: "msd_spring.fmu", kind: "co-simulation", isolated: false },
  ],
  connections: [{ source: "msd1.m1.x1", target: "msd2.m2.x1" }],
  algorithm: { kind: "fixed-step", size: 0.001, min_size: null, max_size: null, master: "gauss-seidel" },
  start_time: 0,
  end_time: 10,
  loops: [],
};
const cosim = (id: number, name: string, state: string, progress: number) => ({
  id, name, owner: "ann", twin: id === 1 ? "rig" : null, prefix: "", mode: "batch", factor: 1, state, progress,
  sim_time: progress * 10, message: "", created_at: 1.7e18, started_at: null, ended_at: null, system, columns: [], rows: 0,
});

function Opened() {
  const state = useLocation().state as { startError?: string } | null;
  return <p>page of {useParams().id}{state?.startError ? `: ${state.startError}` : ""}</p>;
}

function renderPage(impl: (url: string, init?: RequestInit) => Response) {
  setToken("tl_x");
  const fetch = mockFetch(impl);
  render(
    <MemoryRouter initialEntries={["/cosims"]} future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <Routes>
        <Route path="/cosims" element={<CosimsPage />} />
        <Route path="/cosims/:id" element={<Opened />} />
      </Routes>
    </MemoryRouter>,
  );
  return fetch;
}

const twins = jsonResponse({ items: [{ slug: "rig", id: "dt:rig", name: "Rig" }], next_cursor: null });

describe("CosimsPage", () => {
  it("lists the co-simulations with their states and progress, linked to their pages", async () => {
    renderPage((url) => (url === "/api/v1/cosims" ? jsonResponse({ cosims: [cosim(1, "msd", "running", 0.42), cosim(2, "chain", "failed", 0.1)] }) : problem(404, url)));
    const table = await screen.findByRole("table", { name: "Co-simulations" });
    const [, a, b] = within(table).getAllByRole("row");
    expect(within(a!).getByText("running")).toHaveClass("cosim-state-running");
    expect(within(a!).getByRole("progressbar", { name: "Progress" })).toHaveAttribute("value", "0.42");
    expect(within(a!).getByText("42%")).toBeInTheDocument();
    expect(within(a!).getAllByRole("link").map((l) => l.getAttribute("href"))).toEqual(["/cosims/1", "/twins/rig"]);
    expect(within(b!).getByText("failed")).toHaveClass("cosim-state-failed");
    expect(within(b!).getByText("none")).toBeInTheDocument();
  });

  it("says what to do when there is none", async () => {
    renderPage((url) => (url === "/api/v1/cosims" ? jsonResponse({ cosims: [] }) : problem(404, url)));
    expect(await screen.findByText(/No co-simulation yet/)).toBeInTheDocument();
  });

  it("uploads a file with its name, twin and mode, starts it and opens its page", async () => {
    const fetch = renderPage((url, init) => {
      if (url === "/api/v1/cosims") return jsonResponse({ cosims: [] });
      if (url.startsWith("/api/v1/twins?")) return twins;
      if (url.startsWith("/api/v1/cosims?") && init?.method === "POST") return jsonResponse(cosim(7, "msd-mm", "created", 0), 201);
      if (url === "/api/v1/cosims/7/start") return jsonResponse(cosim(7, "msd-mm", "running", 0));
      return problem(404, url);
    });
    await userEvent.click(await screen.findByRole("button", { name: "New co-simulation" }));
    const form = screen.getByRole("form", { name: "New co-simulation" });
    const file = new File(['{"fmus": {}}'], "msd mm.json", { type: "" });
    await userEvent.upload(within(form).getByLabelText("File"), file);
    expect(within(form).getByLabelText("Name")).toHaveValue("msd-mm");
    await within(form).findByRole("option", { name: "rig" });
    await userEvent.selectOptions(within(form).getByLabelText("Twin"), "rig");
    await userEvent.type(within(form).getByLabelText("Signal prefix"), "sim.");
    await userEvent.type(within(form).getByLabelText("Stream"), "model");
    await userEvent.selectOptions(within(form).getByLabelText("Mode"), "realtime");
    await userEvent.clear(within(form).getByLabelText("Speed factor"));
    await userEvent.type(within(form).getByLabelText("Speed factor"), "2");
    await userEvent.click(within(form).getByRole("button", { name: "Create" }));
    expect(await screen.findByText("page of 7")).toBeInTheDocument();
    const post = fetch.mock.calls.find(([url, init]) => String(url).startsWith("/api/v1/cosims?") && init?.method === "POST")!;
    const query = new URL(String(post[0]), "http://x").searchParams;
    expect(Object.fromEntries(query)).toEqual({ name: "msd-mm", twin: "rig", prefix: "sim.", stream: "model", mode: "realtime", factor: "2" });
    expect(post[1]?.body).toBe(file);
    expect((post[1]?.headers as Record<string, string>)["Content-Type"]).toBe("application/json");
    expect(fetch.mock.calls.some(([url, init]) => url === "/api/v1/cosims/7/start" && init?.method === "POST")).toBe(true);
  });

  it("refuses a file it cannot send, and shows the server's objection", async () => {
    const fetch = renderPage((url, init) => {
      if (url === "/api/v1/cosims") return jsonResponse({ cosims: [] });
      if (url.startsWith("/api/v1/twins?")) return twins;
      if (init?.method === "POST") return problem(422, "mm.json: connections: {msd9}.m.x names no FMU in fmus");
      return problem(404, url);
    });
    await userEvent.click(await screen.findByRole("button", { name: "New co-simulation" }));
    const form = screen.getByRole("form", { name: "New co-simulation" });
    await userEvent.upload(within(form).getByLabelText("File"), new File(["x"], "model.fmu"), { applyAccept: false });
    await userEvent.click(within(form).getByRole("button", { name: "Create" }));
    expect(within(form).getByText(/model\.fmu is none of \.json/)).toBeInTheDocument();
    expect(fetch.mock.calls.some(([, init]) => init?.method === "POST")).toBe(false);
    await userEvent.upload(within(form).getByLabelText("File"), new File(["{}"], "mm.json"));
    await userEvent.click(within(form).getByRole("checkbox", { name: "Start it now" }));
    await userEvent.click(within(form).getByRole("button", { name: "Create" }));
    expect(await within(form).findByRole("alert")).toHaveTextContent("(422): mm.json: connections: {msd9}.m.x names no FMU in fmus");
    await waitFor(() => expect(fetch.mock.calls.filter(([, init]) => init?.method === "POST")).toHaveLength(1));
  });

  it("opens the page of one it made but could not start, with the reason", async () => {
    renderPage((url, init) => {
      if (url === "/api/v1/cosims") return jsonResponse({ cosims: [] });
      if (url.startsWith("/api/v1/twins?")) return twins;
      if (url.startsWith("/api/v1/cosims?") && init?.method === "POST") return jsonResponse(cosim(8, "loop", "created", 0), 201);
      if (url === "/api/v1/cosims/8/start") return problem(422, "the system has algebraic loops");
      return problem(404, url);
    });
    await userEvent.click(await screen.findByRole("button", { name: "New co-simulation" }));
    const form = screen.getByRole("form", { name: "New co-simulation" });
    await userEvent.upload(within(form).getByLabelText("File"), new File(["a: 1"], "loop.yaml"));
    await userEvent.click(within(form).getByRole("button", { name: "Create" }));
    expect(await screen.findByText("page of 8: the system has algebraic loops")).toBeInTheDocument();
  });
});

describe("contentTypeOf and nameFromFile", () => {
  it("send each kind of file as the server reads it", () => {
    expect(["a.json", "a.YAML", "a.yml", "a.ssp", "a.zip", "a.tar", "a.tar.gz", "a.tgz", "a.fmu"].map(contentTypeOf)).toEqual([
      "application/json", "application/yaml", "application/yaml", "application/zip", "application/zip",
      "application/x-tar", "application/gzip", "application/gzip", null,
    ]);
    expect(nameFromFile("Incubator Plant.ssp")).toBe("incubator-plant");
    expect(nameFromFile("msd.tar.gz")).toBe("msd");
  });
});
