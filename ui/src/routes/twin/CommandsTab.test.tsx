import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, waitFor, within } from "@testing-library/react";
import { MemoryRouter, Outlet, Route, Routes } from "react-router-dom";
import type { Twin, TwinDocument } from "../../api/types";
import { jsonResponse, mockFetch } from "../../test/fetch";
import { CommandsTab } from "./CommandsTab";
import type { TwinContext } from "./context";

afterEach(() => {
  vi.unstubAllGlobals();
  deviceList = { devices };
});

function posted(fetch: ReturnType<typeof mockFetch>) {
  return fetch.mock.calls.filter(([, init]) => init?.method === "POST").map(([, init]) => JSON.parse(String(init?.body)));
}

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

let deviceList: { devices: typeof devices; default_device?: string | null } = { devices };

function api(url: string, init?: RequestInit) {
  if (url.endsWith("/devices")) return jsonResponse(deviceList);
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

  it("preselects the twin's default device, so Send works at once", async () => {
    const fetch = mockFetch(api);
    const document = { interface: { default_device: "b", commands: [{ name: "pause", parameters: [] }] } };
    renderTab({ slug: "tingen", twin: twin("editor", document), reload: () => {} });
    await waitFor(() => expect(screen.getByLabelText(/^Device/)).toHaveValue("b"));
    fireEvent.click(within(screen.getByRole("form", { name: "Command pause" })).getByRole("button", { name: "Send" }));
    await screen.findByTestId("command-outcome");
    expect(posted(fetch)).toEqual([{ name: "pause", args: {}, device: "b" }]);
  });

  it("preselects the device the server names, else the only connected one", async () => {
    deviceList = { devices, default_device: "b" };
    mockFetch(api);
    const { unmount } = renderTab({ slug: "tingen", twin: twin("editor", {}), reload: () => {} });
    await waitFor(() => expect(screen.getByLabelText(/^Device/)).toHaveValue("b"));
    unmount();
    deviceList = { devices };
    renderTab({ slug: "tingen", twin: twin("editor", {}), reload: () => {} });
    await waitFor(() => expect(screen.getByLabelText(/^Device/)).toHaveValue("a")); // a is connected
  });

  it("never sends without a device: with no sensible default it asks to choose one", async () => {
    deviceList = { devices: devices.map((d) => ({ ...d, connected: false })), default_device: null };
    const fetch = mockFetch(api);
    const document = { interface: { commands: [{ name: "pause", parameters: [] }] } };
    renderTab({ slug: "tingen", twin: twin("editor", document), reload: () => {} });
    await waitFor(() => expect(screen.getByRole("option", { name: "choose a device" })).toBeInTheDocument());
    const form = screen.getByRole("form", { name: "Command pause" });
    fireEvent.click(within(form).getByRole("button", { name: "Send" }));
    expect(await within(form.parentElement!).findByRole("alert")).toHaveTextContent("Choose the device to send to in the Device list above.");
    expect(posted(fetch)).toEqual([]);
    fireEvent.change(screen.getByLabelText(/^Device/), { target: { value: "a" } });
    expect(screen.queryByRole("option", { name: "choose a device" })).not.toBeInTheDocument();
    fireEvent.click(within(form).getByRole("button", { name: "Send" }));
    await screen.findByTestId("command-outcome");
    expect(posted(fetch)).toEqual([{ name: "pause", args: {}, device: "a" }]);
  });

  it("filters the log by state", async () => {
    const fetch = mockFetch(api);
    renderTab({ slug: "tingen", twin: twin("editor", {}), reload: () => {} });
    await screen.findByText("bob");
    fireEvent.change(screen.getByLabelText(/^State/), { target: { value: "failed" } });
    await vi.waitFor(() => expect(fetch.mock.calls.some(([url]) => String(url).includes("state=failed"))).toBe(true));
  });
});
