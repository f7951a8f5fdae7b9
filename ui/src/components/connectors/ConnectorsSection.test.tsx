import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { ConnectorsSection } from "./ConnectorsSection";

afterEach(() => {
  vi.unstubAllGlobals();
  vi.restoreAllMocks();
});

const status = {
  state: "listening", since_ns: 1764068000000000000, last_message_ns: 1764068012000000000, messages: 1200,
  samples: 2400, rejected: 0, commands: 0, errors: { truncated: 2 }, error_count: 2,
  last_error: "truncated: 7 bytes", last_error_ns: 1764068011000000000, address: "127.0.0.1:7001",
};
const catman = { name: "catman", twin: "tingen", kind: "udp", device: "catman", enabled: true, config: {}, status };

describe("ConnectorsSection", () => {
  it("shows each connector's state, address, figures and last error", async () => {
    mockFetch(() => jsonResponse({ connectors: [catman] }));
    render(<ConnectorsSection slug="tingen" canManage={false} />);
    const row = (await screen.findAllByRole("row")).find((r) => r.textContent?.includes("catman"))!;
    expect(within(row).getByText("listening")).toHaveClass("badge-ok");
    expect(row).toHaveTextContent("127.0.0.1:7001");
    expect(row).toHaveTextContent("2,400");
    expect(row).toHaveTextContent("truncated: 7 bytes");
    expect(screen.queryByRole("button", { name: "Stop" })).toBeNull();
  });

  it("lets an admin stop a connector and shows it disabled after", async () => {
    let enabled = true;
    const fetch = mockFetch((_url, init) => {
      if (init?.method === "POST") {
        enabled = false;
        return jsonResponse({ ...catman, enabled: false, status: { ...status, state: "stopped" } });
      }
      return jsonResponse({ connectors: [{ ...catman, enabled, status: enabled ? status : { ...status, state: "stopped" } }] });
    });
    render(<ConnectorsSection slug="tingen" canManage />);
    fireEvent.click(await screen.findByRole("button", { name: "Stop" }));
    expect(await screen.findByText("disabled")).toBeInTheDocument();
    expect(fetch.mock.calls.some(([u, i]) => u === "/api/v1/twins/tingen/connectors/catman/stop" && i?.method === "POST")).toBe(true);
    expect(screen.getByRole("button", { name: "Start" })).toBeInTheDocument();
  });

  it("says how to add one when there is none, and shows errors with a retry", async () => {
    mockFetch(() => jsonResponse({ connectors: [] }));
    const { unmount } = render(<ConnectorsSection slug="tingen" canManage />);
    expect(await screen.findByText(/No connectors/)).toBeInTheDocument();
    unmount();
    mockFetch(() => problem(404, "no twin 'x'"));
    render(<ConnectorsSection slug="x" canManage />);
    expect(await screen.findByText(/no twin 'x'/)).toBeInTheDocument();
  });
});
