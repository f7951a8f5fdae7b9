import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { DevicesSection } from "./DevicesSection";

afterEach(() => {
  vi.unstubAllGlobals();
  vi.restoreAllMocks();
});

const T = "2026-11-21T10:00:00.000Z";
const SECRET = "tld_0123456789abcdefghijklmnopqrstuvwxyzABCDEFG";
const sap = { name: "tingenSAP", twin: "tingen", description: "the Pi", token_prefix: "tld_AbCdE", created: T, last_seen: null, connected: false };

describe("DevicesSection", () => {
  it("adds a device and shows its token once, never in the table or storage", async () => {
    let listed: unknown[] = [];
    const fetch = mockFetch((_url, init) => {
      if (init?.method === "POST") {
        listed = [sap];
        return jsonResponse({ ...sap, token: SECRET }, 201);
      }
      return jsonResponse({ devices: listed });
    });
    render(<DevicesSection slug="tingen" canEdit />);
    expect(await screen.findByText("This twin has no devices.")).toBeInTheDocument();
    const form = screen.getByRole("form", { name: "Add a device" });
    fireEvent.change(within(form).getByLabelText("Device name"), { target: { value: "tingenSAP" } });
    fireEvent.change(within(form).getByLabelText("Description"), { target: { value: "the Pi" } });
    fireEvent.click(within(form).getByRole("button", { name: "Add device" }));
    expect(await screen.findByTestId("secret-value")).toHaveValue(SECRET);
    expect(screen.getByText(/shown only this once/)).toBeInTheDocument();
    const post = fetch.mock.calls.find(([, i]) => i?.method === "POST")!;
    expect(post[0]).toBe("/api/v1/twins/tingen/devices");
    expect(JSON.parse(String(post[1]?.body))).toEqual({ name: "tingenSAP", description: "the Pi" });
    const row = (await screen.findByText("tld_AbCdE…")).closest("tr")!;
    expect(row).not.toHaveTextContent(SECRET);
    expect(JSON.stringify({ ...sessionStorage })).not.toContain(SECRET);
    expect(JSON.stringify({ ...localStorage })).not.toContain(SECRET);
    fireEvent.click(screen.getByRole("button", { name: "I have saved it" }));
    expect(screen.queryByTestId("secret-value")).not.toBeInTheDocument();
    expect(document.body).not.toHaveTextContent(SECRET);
  });

  it("replaces a token after confirming, and shows a refusal", async () => {
    vi.spyOn(window, "confirm").mockReturnValue(true);
    const fetch = mockFetch((url, init) => {
      if (url.endsWith("/token")) return jsonResponse({ ...sap, token: SECRET });
      if (init?.method === "DELETE") return problem(403, "deleting a device needs the editor role");
      return jsonResponse({ devices: [sap] });
    });
    render(<DevicesSection slug="tingen" canEdit />);
    fireEvent.click(await screen.findByRole("button", { name: "New token" }));
    expect(await screen.findByTestId("secret-value")).toHaveValue(SECRET);
    expect(fetch.mock.calls.some(([u, i]) => u === "/api/v1/twins/tingen/devices/tingenSAP/token" && i?.method === "POST")).toBe(true);
    fireEvent.click(screen.getByRole("button", { name: "Delete" }));
    expect(await screen.findByRole("alert")).toHaveTextContent("(403)");
  });

  it("does not delete when the confirmation is declined; viewers get no buttons", async () => {
    vi.spyOn(window, "confirm").mockReturnValue(false);
    const fetch = mockFetch(() => jsonResponse({ devices: [sap] }));
    const { unmount } = render(<DevicesSection slug="tingen" canEdit />);
    fireEvent.click(await screen.findByRole("button", { name: "Delete" }));
    expect(fetch.mock.calls.every(([, i]) => (i?.method ?? "GET") === "GET")).toBe(true);
    unmount();
    render(<DevicesSection slug="tingen" canEdit={false} />);
    await screen.findByText("tingenSAP");
    expect(screen.queryByRole("button", { name: "Delete" })).not.toBeInTheDocument();
    expect(screen.queryByRole("form", { name: "Add a device" })).not.toBeInTheDocument();
  });
});
