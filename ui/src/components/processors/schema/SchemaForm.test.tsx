import { describe, expect, it, vi } from "vitest";
import { useState } from "react";
import { fireEvent, render, screen, within } from "@testing-library/react";
import type { JsonSchema } from "../../../api/processors";
import { fmuBlueprint, lowpassBlueprint, triggerBlueprint, windowBlueprint } from "../test/blueprints";
import { SchemaForm } from "./SchemaForm";

type Value = Record<string, unknown>;

interface HarnessProps {
  schema: JsonSchema;
  initial?: Value;
  errors?: Record<string, string>;
  suggestions?: string[];
  omit?: string[];
  onValidity?: (valid: boolean) => void;
}

/** Render the form on a value it owns; answers a function giving the latest value. */
function renderForm({ initial = {}, ...props }: HarnessProps) {
  const seen = vi.fn<(value: Value) => void>();
  function Harness() {
    const [value, setValue] = useState<Value>(initial);
    return (
      <SchemaForm
        {...props}
        path="params"
        value={value}
        onChange={(next) => {
          setValue(next);
          seen(next);
        }}
      />
    );
  }
  render(<Harness />);
  return () => seen.mock.lastCall?.[0];
}

const type = (label: string | RegExp, value: string) => fireEvent.change(screen.getByLabelText(label), { target: { value } });

describe("SchemaForm on the trigger blueprint ($defs, optional fields, enums)", () => {
  it("shows titles, required marks, defaults and limits, and produces typed values", () => {
    const latest = renderForm({ schema: triggerBlueprint.params_schema! });
    const signal = screen.getByLabelText("Signal");
    expect(signal.closest(".sf-field")).toHaveTextContent("required");
    expect(screen.getByLabelText("Clear Fraction").closest(".sf-field")).toHaveTextContent("Default: 0.8. Allowed: > 0, ≤ 1.");
    const mode = screen.getByLabelText("Mode");
    expect(within(mode).getByRole("option", { name: "default (threshold)" })).toBeInTheDocument();

    type("Signal", "Cantilever_Angle_radians");
    fireEvent.change(mode, { target: { value: "1" } }); // the second choice: rate
    type("Rate Limit", "2.5");
    type("Min Duration S", "0.05");
    expect(latest()).toEqual({ signal: "Cantilever_Angle_radians", mode: "rate", rate_limit: 2.5, min_duration_s: 0.05 });

    type("Rate Limit", ""); // an emptied optional field is left out: the server's default applies
    fireEvent.change(mode, { target: { value: "" } });
    expect(latest()).toEqual({ signal: "Cantilever_Angle_radians", min_duration_s: 0.05 });
  });

  it("edits an optional nested object from $defs, with a raw JSON fallback for free-form params", () => {
    const validity = vi.fn();
    const latest = renderForm({ schema: triggerBlueprint.params_schema!, onValidity: validity });
    const command = screen.getByRole("group", { name: /^Command/ });
    expect(within(command).queryByLabelText("Name")).not.toBeInTheDocument();
    fireEvent.click(within(command).getByLabelText("Set Command"));
    fireEvent.change(within(command).getByLabelText("Name"), { target: { value: "pause" } });
    const params = within(command).getByLabelText("Params");
    fireEvent.change(params, { target: { value: '{"speed": 2}' } });
    expect(latest()).toEqual({ command: { name: "pause", params: { speed: 2 } } });

    fireEvent.change(params, { target: { value: '{"speed": ' } });
    expect(within(command).getByText("This is not valid JSON yet.")).toBeInTheDocument();
    expect(validity).toHaveBeenLastCalledWith(false);
    expect(latest()).toEqual({ command: { name: "pause", params: { speed: 2 } } }); // the last good value
    fireEvent.change(params, { target: { value: "" } });
    expect(validity).toHaveBeenLastCalledWith(true);

    fireEvent.click(within(command).getByLabelText("Set Command"));
    expect(latest()).toEqual({});
  });
});

describe("SchemaForm on lists, maps and given values", () => {
  it("edits a list of choices as checkboxes and a list of signals as text with suggestions", () => {
    const latest = renderForm({ schema: windowBlueprint.params_schema!, suggestions: ["x", "y"] });
    const functions = screen.getByRole("group", { name: /^Functions/ });
    fireEvent.click(within(functions).getByLabelText("max"));
    fireEvent.click(within(functions).getByLabelText("mean"));
    type("Signals", "a, b,");
    expect(screen.getByLabelText("Signals")).toHaveValue("a, b,"); // the text stays as typed
    fireEvent.click(screen.getByRole("button", { name: "+ x" }));
    type("Window Samples", "100");
    expect(latest()).toEqual({ functions: ["mean", "max"], signals: ["a", "b", "x"], window_samples: 100 });
    expect(screen.getByLabelText("Signals")).toHaveValue("a, b, x");
  });

  it("edits a map of scalars (an FMU's parameters) as rows and skips omitted fields", () => {
    const latest = renderForm({ schema: fmuBlueprint.params_schema!, initial: { fmu: "T.fmu", parameters: { L: 0.3 } }, omit: ["fmu"] });
    expect(screen.queryByLabelText("Fmu")).not.toBeInTheDocument();
    expect(screen.getByLabelText("Parameters: name 1")).toHaveValue("L");
    expect(screen.getByLabelText("Parameters: value 1")).toHaveValue("0.3");
    fireEvent.click(screen.getByRole("button", { name: "Add entry" }));
    type("Parameters: name 2", "zeta");
    type("Parameters: value 2", "0.7");
    expect(latest()).toEqual({ fmu: "T.fmu", parameters: { L: 0.3, zeta: 0.7 } });
    fireEvent.click(screen.getByRole("button", { name: "Remove Parameters entry 1" }));
    expect(latest()).toEqual({ fmu: "T.fmu", parameters: { zeta: 0.7 } });
  });

  it("shows the values it is given and the server's message at the field it names", () => {
    renderForm({
      schema: lowpassBlueprint.params_schema!,
      initial: { signals: ["Cantilever_Angle_radians"], cutoff_hz: 0, sample_rate_hz: 100 },
      errors: { "params.cutoff_hz": "Input should be greater than 0" },
    });
    expect(screen.getByLabelText("Signals")).toHaveValue("Cantilever_Angle_radians");
    const cutoff = screen.getByLabelText("Cutoff Hz");
    expect(cutoff).toHaveValue(0);
    const field = cutoff.closest(".sf-field")!;
    expect(field).toHaveClass("sf-field-bad");
    expect(field).toHaveTextContent("Input should be greater than 0");
    expect(cutoff.getAttribute("aria-describedby")).toContain("-error");
    expect(screen.getByLabelText("Sample Rate Hz").closest(".sf-field")).not.toHaveClass("sf-field-bad");
  });
});
