import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, waitFor, within } from "@testing-library/react";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { CreateProcessor } from "./CreateProcessor";
import { fakeApi, processor } from "./test/api";

afterEach(() => vi.unstubAllGlobals());

const isCreate = (url: string, init?: RequestInit) => url === "/api/v1/twins/tingen/processors" && init?.method === "POST";

/** Wait for a field; loads chain (blueprint, FMU list, FMU variables), so allow some time. */
const findField = (label: string) => screen.findByLabelText(label, {}, { timeout: 4000 });

function renderCreate() {
  const onCreated = vi.fn();
  render(<CreateProcessor slug="tingen" existing={[]} fmusVersion={0} onCreated={onCreated} onCancel={() => {}} />);
  return onCreated;
}

function sentBody(fetch: ReturnType<typeof mockFetch>): unknown {
  const call = fetch.mock.calls.find(([url, init]) => isCreate(String(url), init));
  return call ? JSON.parse(String(call[1]?.body)) : undefined;
}

describe("CreateProcessor", () => {
  it("creates the Tingen FMU processor in a few steps with the mapping view", async () => {
    const fetch = mockFetch(fakeApi((url, init) => (isCreate(url, init) ? jsonResponse(processor({ state: "starting" }), 201) : null)));
    const onCreated = renderCreate();
    fireEvent.change(await findField("Blueprint"), { target: { value: "fmu" } });
    expect(screen.getByLabelText("About fmu")).toHaveTextContent("Runs an FMU");
    const fmu = await findField("FMU");
    await waitFor(() => expect(fmu).toHaveValue("Tingen.fmu"), { timeout: 4000 }); // the only one: chosen
    const signal = await findField("Signal for F");
    expect(signal).toHaveValue(""); // no signal is called F: not fed until chosen
    fireEvent.change(signal, { target: { value: "Input_F_in" } });
    const outputs = screen.getByRole("group", { name: "Outputs written to the output stream" });
    for (const name of ["theta", "sigma", "w"]) expect(within(outputs).getByLabelText(name)).toBeChecked();
    expect(screen.getByLabelText("Value of zeta")).toHaveAttribute("placeholder", "0.02");
    expect(screen.getByLabelText("Name")).toHaveValue("fmu");

    fireEvent.click(screen.getByRole("button", { name: "Create processor" }));
    await waitFor(() => expect(onCreated).toHaveBeenCalled(), { timeout: 4000 });
    expect(sentBody(fetch)).toEqual({
      name: "fmu",
      blueprint: "fmu",
      source: "telemetry",
      enabled: true,
      inputs: { F: { signal: "Input_F_in", scale: 1, offset: 0 } },
      params: { fmu: "Tingen.fmu", outputs: ["theta", "sigma", "w"] },
    });
  });

  it("sends scale, offset, chosen outputs and parameters", async () => {
    const fetch = mockFetch(fakeApi((url, init) => (isCreate(url, init) ? jsonResponse(processor(), 201) : null)));
    renderCreate();
    fireEvent.change(await findField("Blueprint"), { target: { value: "fmu" } });
    fireEvent.change(await findField("Signal for F"), { target: { value: "Input_F_in" } });
    fireEvent.change(screen.getByLabelText("Scale for F"), { target: { value: "0.5" } });
    fireEvent.change(screen.getByLabelText("Offset for F"), { target: { value: "-1" } });
    fireEvent.click(screen.getByLabelText("w"));
    fireEvent.change(screen.getByLabelText("Value of zeta"), { target: { value: "0.7" } });
    fireEvent.change(screen.getByLabelText("Step"), { target: { value: "1" } }); // fixed, from the generated form
    fireEvent.click(screen.getByRole("button", { name: "Create processor" }));
    await waitFor(() => expect(sentBody(fetch)).toBeDefined(), { timeout: 4000 });
    expect(sentBody(fetch)).toMatchObject({
      inputs: { F: { signal: "Input_F_in", scale: 0.5, offset: -1 } },
      params: { fmu: "Tingen.fmu", outputs: ["theta", "sigma"], parameters: { zeta: 0.7 }, step: "fixed" },
    });
  });

  it("posts the generated form's values and shows a 422 at the field it names", async () => {
    const fetch = mockFetch(
      fakeApi((url, init) => (isCreate(url, init) ? problem(422, "params: cutoff_hz: Input should be greater than 0") : null)),
    );
    const onCreated = renderCreate();
    fireEvent.change(await findField("Blueprint"), { target: { value: "lowpass" } });
    fireEvent.change(await findField("Signals"), { target: { value: "Cantilever_Angle_radians" } });
    fireEvent.change(screen.getByLabelText("Sample Rate Hz"), { target: { value: "100" } });
    fireEvent.change(screen.getByLabelText("Cutoff Hz"), { target: { value: "0" } });
    fireEvent.change(screen.getByLabelText("Name"), { target: { value: "smooth" } });
    fireEvent.click(screen.getByRole("button", { name: "Create processor" }));

    const field = (await screen.findByText("Input should be greater than 0", {}, { timeout: 4000 })).closest(".sf-field");
    expect(field).toHaveAttribute("data-path", "params.cutoff_hz");
    expect(screen.getByText(/see the fields marked below/)).toBeInTheDocument();
    expect(sentBody(fetch)).toEqual({
      name: "smooth",
      blueprint: "lowpass",
      source: "telemetry",
      enabled: true,
      params: { signals: ["Cantilever_Angle_radians"], sample_rate_hz: 100, cutoff_hz: 0 },
    });
    expect(onCreated).not.toHaveBeenCalled();
  });

  it("shows an error that names no field on top", async () => {
    mockFetch(fakeApi((url, init) => (isCreate(url, init) ? problem(409, "the twin already has a processor 'fmu'") : null)));
    renderCreate();
    fireEvent.change(await findField("Blueprint"), { target: { value: "fmu" } });
    await findField("Signal for F");
    fireEvent.click(screen.getByRole("button", { name: "Create processor" }));
    expect(await screen.findByRole("alert", {}, { timeout: 4000 })).toHaveTextContent("the twin already has a processor 'fmu'");
  });
});
