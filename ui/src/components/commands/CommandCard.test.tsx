import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import { readInterface, type CommandRecord } from "../../api/commands";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { CommandCard } from "./CommandCard";

afterEach(() => vi.unstubAllGlobals());

const iface = readInterface({
  interface: {
    commands: [
      {
        name: "configure",
        description: "Set up the rig.",
        parameters: [
          { name: "rate", type: "number", unit: "Hz", min: 1, max: 100, required: true },
          { name: "count", type: "integer", default: 3 },
          { name: "verbose", type: "bool", default: true },
          { name: "label", type: "string" },
        ],
      },
    ],
  },
});
const configure = iface.commands[0]!;

function record(over: Partial<CommandRecord>): CommandRecord {
  return {
    id: "c1", twin: "tingen", device: "tingenSAP", name: "configure", args: {}, state: "succeeded", queued: false,
    sent_by: "alice", created: "2026-11-21T10:00:00.000Z", expires: "2026-11-21T10:00:10.000Z",
    delivered: "2026-11-21T10:00:00.010Z", finished: "2026-11-21T10:00:00.042Z", result: null, error: null, late_status: null,
    ...over,
  };
}

function renderCard(disabled = false) {
  const onSent = vi.fn();
  render(<CommandCard slug="tingen" command={configure} target={{ queue: false }} disabled={disabled} onSent={onSent} />);
  return { form: screen.getByRole("form", { name: "Command configure" }), onSent };
}

describe("CommandCard", () => {
  it("builds inputs from the parameters: types, limits, required marks and defaults", () => {
    const { form } = renderCard();
    const rate = within(form).getByLabelText(/^rate/);
    expect(rate).toHaveAttribute("type", "number");
    expect(rate).toHaveAttribute("min", "1");
    expect(rate).toHaveAttribute("max", "100");
    expect(rate).toBeRequired();
    expect(within(form).getByText("number · 1 to 100 Hz")).toBeInTheDocument();
    expect(within(form).getByLabelText(/^count/)).toHaveValue(3);
    expect(within(form).getByLabelText(/^count/)).toHaveAttribute("step", "1");
    expect(within(form).getByLabelText(/^verbose/)).toBeChecked();
    expect(within(form).getByLabelText(/^label/)).toHaveAttribute("type", "text");
    expect(within(form).getAllByTitle("required")).toHaveLength(1);
    expect(screen.getByText("Set up the rig.")).toBeInTheDocument();
  });

  it("posts the typed arguments and shows the result", async () => {
    const fetch = mockFetch(() => jsonResponse(record({ args: { rate: 50, count: 3, verbose: false }, result: { rate: 50 } })));
    const { form, onSent } = renderCard();
    fireEvent.change(within(form).getByLabelText(/^rate/), { target: { value: "50" } });
    fireEvent.click(within(form).getByLabelText(/^verbose/));
    fireEvent.click(within(form).getByRole("button", { name: "Send" }));
    const outcome = await screen.findByTestId("command-outcome");
    const [url, init] = fetch.mock.calls[0]!;
    expect(url).toBe("/api/v1/twins/tingen/commands");
    expect(init?.method).toBe("POST");
    // the empty optional string is left out so the server fills its default
    expect(JSON.parse(String(init?.body))).toEqual({ name: "configure", args: { rate: 50, count: 3, verbose: false } });
    expect(within(outcome).getByText("succeeded")).toHaveClass("state-succeeded");
    expect(outcome).toHaveTextContent("took 42 ms");
    expect(outcome.querySelector("pre")?.textContent).toContain('"rate": 50');
    expect(onSent).toHaveBeenCalled();
  });

  it("refuses a missing required value without sending", async () => {
    const fetch = mockFetch(() => jsonResponse({}));
    const { form } = renderCard();
    fireEvent.click(within(form).getByRole("button", { name: "Send" }));
    expect(await screen.findByRole("alert")).toHaveTextContent("rate is required");
    expect(fetch).not.toHaveBeenCalled();
  });

  it("shows the server's 422 reason", async () => {
    mockFetch(() => problem(422, "configure: argument 'rate': 500 is above the maximum 100"));
    const { form } = renderCard();
    fireEvent.change(within(form).getByLabelText(/^rate/), { target: { value: "500" } });
    fireEvent.click(within(form).getByRole("button", { name: "Send" }));
    const alert = await screen.findByRole("alert");
    expect(alert).toHaveTextContent("(422)");
    expect(alert).toHaveTextContent("500 is above the maximum 100");
  });

  it("shows a failed command's error", async () => {
    mockFetch(() => jsonResponse(record({ state: "failed", error: "device offline", delivered: null })));
    const { form } = renderCard();
    fireEvent.change(within(form).getByLabelText(/^rate/), { target: { value: "5" } });
    fireEvent.click(within(form).getByRole("button", { name: "Send" }));
    const outcome = await screen.findByTestId("command-outcome");
    expect(within(outcome).getByText("failed")).toHaveClass("state-failed");
    expect(outcome).toHaveTextContent("Error: device offline");
  });

  it("queues a command without waiting, then checks it until it has ended", async () => {
    const fetch = mockFetch((_url, init) =>
      init?.method === "POST"
        ? jsonResponse(record({ state: "pending", queued: true, delivered: null, finished: null }), 202)
        : jsonResponse(record({ state: "succeeded", queued: true, result: { ok: 1 } })),
    );
    render(<CommandCard slug="tingen" command={configure} target={{ queue: true, device: "b", timeoutS: 60 }} disabled={false} onSent={() => {}} />);
    fireEvent.change(screen.getByLabelText(/^rate/), { target: { value: "5" } });
    fireEvent.click(screen.getByRole("button", { name: "Send" }));
    expect(await screen.findByText("waiting for the device…")).toBeInTheDocument();
    expect(JSON.parse(String(fetch.mock.calls[0]![1]?.body))).toEqual({
      name: "configure", args: { rate: 5, count: 3, verbose: true }, device: "b", timeout_s: 60, queue: true, wait: false,
    });
    expect(await screen.findByText("succeeded", {}, { timeout: 4000 })).toBeInTheDocument();
    expect(fetch.mock.calls[1]![0]).toBe("/api/v1/twins/tingen/commands/c1");
  });

  it("disables the form for viewers", () => {
    const { form } = renderCard(true);
    expect(within(form).getByRole("button", { name: "Send" })).toBeDisabled();
    expect(within(form).getByLabelText(/^rate/)).toBeDisabled();
  });
});
