import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import { MemoryRouter, Outlet, Route, Routes } from "react-router-dom";
import type { Twin, TwinDocument } from "../../api/types";
import { jsonResponse, mockFetch } from "../../test/fetch";
import { CommandsTab } from "./CommandsTab";
import type { TwinContext } from "./context";

afterEach(() => vi.unstubAllGlobals());

const T = "2026-11-21T10:00:00.000Z";

function twin(role: Twin["role"], document: TwinDocument): Twin {
  return { slug: "tingen", id: "x", name: "Tingen", url: "", created: T, modified: T, levels: ["public"], role, document };
}

function renderTab(context: TwinContext) {
  return render(
    <MemoryRouter initialEntries={["/twins/tingen/commands"]} future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <Routes>
        <Route path="/twins/:slug" element={<Outlet context={context} />}>
          <Route path="commands" element={<CommandsTab />} />
        </Route>
      </Routes>
    </MemoryRouter>,
  );
}

const devices = [
  { name: "a", twin: "tingen", created: T, last_seen: null, connected: true },
  { name: "b", twin: "tingen", created: T, last_seen: null, connected: false },
];
const emptyProps = { device: "a", reported: {}, desired: {}, delta: {}, version: 0 };
const logEntry = {
  id: "c9", twin: "tingen", device: "a", name: "pause", args: {}, state: "expired", queued: false, sent_by: "bob",
  created: T, expires: T, delivered: null, finished: T, result: null, error: null, late_status: null,
};

function api(url: string, init?: RequestInit) {
  if (url.endsWith("/devices")) return jsonResponse({ devices });
  if (url.includes("/properties")) return jsonResponse(emptyProps);
  if (url.startsWith("/api/v1/twins/tingen/commands") && init?.method === "POST") return jsonResponse({ ...logEntry, state: "succeeded" });
  if (url.startsWith("/api/v1/twins/tingen/commands")) return jsonResponse({ commands: [logEntry] });
  return jsonResponse({});
}

describe("CommandsTab", () => {
  it("shows viewers the forms disabled with a note, and the log", async () => {
    mockFetch(api);
    const document = { interface: { commands: [{ name: "pause", parameters: [] }] } };
    renderTab({ slug: "tingen", twin: twin("viewer", document), reload: () => {} });
    expect(screen.getByText(/needs the editor role/)).toBeInTheDocument();
    expect(within(screen.getByRole("form", { name: "Command pause" })).getByRole("button", { name: "Send" })).toBeDisabled();
    const log = await screen.findByText("bob");
    expect(log.closest("tr")).toHaveTextContent("expired");
  });

  it("offers a free command form when the interface declares none, sent to the chosen device", async () => {
    const fetch = mockFetch(api);
    renderTab({ slug: "tingen", twin: twin("editor", {}), reload: () => {} });
    const form = screen.getByRole("form", { name: "Free command" });
    fireEvent.change(await screen.findByLabelText(/^Device/), { target: { value: "b" } });
    fireEvent.change(within(form).getByLabelText("Command name"), { target: { value: "blink" } });
    fireEvent.change(within(form).getByLabelText("Arguments (JSON object)"), { target: { value: '{"times": 3}' } });
    fireEvent.click(within(form).getByRole("button", { name: "Send" }));
    await screen.findByTestId("command-outcome");
    const post = fetch.mock.calls.find(([, init]) => init?.method === "POST")!;
    expect(JSON.parse(String(post[1]?.body))).toEqual({ name: "blink", args: { times: 3 }, device: "b" });
  });

  it("filters the log by state", async () => {
    const fetch = mockFetch(api);
    renderTab({ slug: "tingen", twin: twin("editor", {}), reload: () => {} });
    await screen.findByText("bob");
    fireEvent.change(screen.getByLabelText(/^State/), { target: { value: "failed" } });
    await vi.waitFor(() => expect(fetch.mock.calls.some(([url]) => String(url).includes("state=failed"))).toBe(true));
  });
});
