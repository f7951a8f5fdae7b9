import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import { readInterface, type DeviceProperties } from "../../api/commands";
import type { Device } from "../../api/types";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { PropertiesPanel } from "./PropertiesPanel";

afterEach(() => vi.unstubAllGlobals());

const decls = readInterface({
  interface: {
    properties: [
      { name: "sample_rate", type: "number", unit: "Hz", min: 1, max: 100, writable: true },
      { name: "paused", type: "bool", writable: false },
      { name: "mode", type: "string", writable: true },
    ],
  },
}).properties;

const device: Device = {
  name: "tingenSAP",
  twin: "tingen",
  description: "",
  token_prefix: "tld_x",
  created: "2026-11-21T09:00:00Z",
  last_seen: "2026-11-21T10:00:00Z",
  connected: true,
};
const T = "2026-11-21T10:00:00.000Z";

function props(over: Partial<DeviceProperties> = {}): DeviceProperties {
  return {
    device: "tingenSAP",
    reported: { sample_rate: { value: 100, time: T }, paused: { value: false, time: T } },
    desired: { sample_rate: { value: 50, time: T } },
    delta: { sample_rate: 50 },
    version: 4,
    ...over,
  };
}

describe("PropertiesPanel", () => {
  it("shows reported against desired values with the delta marker and the device's state", async () => {
    mockFetch(() => jsonResponse(props()));
    render(<PropertiesPanel slug="tingen" device={device} decls={decls} editable={false} />);
    const table = await screen.findByRole("table");
    const rate = within(table).getByText("sample_rate").closest("tr")!;
    expect(rate).toHaveTextContent("100");
    expect(rate).toHaveTextContent("50");
    expect(within(rate).getByText("≠ not applied")).toBeInTheDocument();
    const paused = within(table).getByText("paused").closest("tr")!;
    expect(paused).toHaveTextContent("false");
    expect(paused).not.toHaveTextContent("not applied");
    expect(within(table).getByText("mode").closest("tr")).toHaveTextContent("not reported");
    expect(screen.getByText("connected")).toBeInTheDocument();
    expect(screen.getByTestId("desired-version")).toHaveTextContent("desired version 4");
    expect(screen.queryByRole("textbox")).not.toBeInTheDocument();
  });

  it("lets editors change writable values only and PATCHes the typed changes", async () => {
    const fetch = mockFetch((_url, init) =>
      init?.method === "PATCH"
        ? jsonResponse(props({ desired: { sample_rate: { value: 20, time: T }, mode: { value: "fast", time: T } }, delta: { sample_rate: 20, mode: "fast" }, version: 5 }))
        : jsonResponse(props()),
    );
    render(<PropertiesPanel slug="tingen" device={device} decls={decls} editable />);
    const rate = await screen.findByLabelText("Desired sample_rate");
    expect(rate).toHaveValue(50);
    expect(screen.queryByLabelText("Desired paused")).not.toBeInTheDocument();
    fireEvent.change(rate, { target: { value: "20" } });
    fireEvent.change(screen.getByLabelText("Desired mode"), { target: { value: "fast" } });
    fireEvent.click(screen.getByRole("button", { name: "Save 2 desired values" }));
    expect(await screen.findByText("Saved: desired version 5.")).toBeInTheDocument();
    const [url, init] = fetch.mock.calls[1]!;
    expect(url).toBe("/api/v1/twins/tingen/devices/tingenSAP/properties/desired");
    expect(init?.method).toBe("PATCH");
    expect(JSON.parse(String(init?.body))).toEqual({ sample_rate: 20, mode: "fast" });
    expect(screen.getByLabelText("Desired sample_rate")).toHaveValue(20);
  });

  it("removes a desired value with null and shows a refusal", async () => {
    const fetch = mockFetch((_url, init) =>
      init?.method === "PATCH" ? problem(422, "the property 'sample_rate' is not writable (set by the device)") : jsonResponse(props()),
    );
    render(<PropertiesPanel slug="tingen" device={device} decls={decls} editable />);
    fireEvent.click(await screen.findByRole("button", { name: "Remove" }));
    expect(await screen.findByRole("alert")).toHaveTextContent("not writable");
    expect(JSON.parse(String(fetch.mock.calls[1]![1]?.body))).toEqual({ sample_rate: null });
  });

  it("takes any name and loosely typed value when the interface declares no properties", async () => {
    const fetch = mockFetch((_url, init) => (init?.method === "PATCH" ? jsonResponse(props({ version: 5 })) : jsonResponse(props())));
    render(<PropertiesPanel slug="tingen" device={device} decls={[]} editable />);
    fireEvent.change(await screen.findByLabelText("Desired paused"), { target: { value: "true" } });
    fireEvent.click(screen.getByRole("button", { name: "Save 1 desired value" }));
    await screen.findByText("Saved: desired version 5.");
    expect(JSON.parse(String(fetch.mock.calls[1]![1]?.body))).toEqual({ paused: true });
    fireEvent.change(screen.getByLabelText("New property name"), { target: { value: "label" } });
    fireEvent.change(screen.getByLabelText("New property value"), { target: { value: "north" } });
    fireEvent.click(screen.getByRole("button", { name: "Set desired" }));
    await vi.waitFor(() => expect(fetch).toHaveBeenCalledTimes(3));
    expect(JSON.parse(String(fetch.mock.calls[2]![1]?.body))).toEqual({ label: "north" });
  });
});
