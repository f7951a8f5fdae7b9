import { describe, expect, it } from "vitest";
import { buildFmuParts, buildSpec, freeName, initialFmuChoice, type CreateDraft } from "./buildSpec";
import { tingenFmu } from "./test/tingen";

const variables = tingenFmu.variables!;

function draft(change: Partial<CreateDraft>): CreateDraft {
  return { name: "fmu", blueprint: "fmu", source: "telemetry", output: "", enabled: true, inputs: [], params: {}, limits: { rates: {} }, fmu: null, ...change };
}

describe("the FMU mapping's inputs and params", () => {
  it("starts with every output chosen and inputs fed only from signals of their own name", () => {
    const choice = initialFmuChoice("Tingen.fmu", variables, ["Input_F_in", "Cantilever_Angle_radians"]);
    expect(choice.feeds).toEqual({ F: { signal: "" } });
    expect(choice.outputs).toEqual(["theta", "sigma", "w"]);
    expect(initialFmuChoice("Tingen.fmu", variables, ["F"]).feeds).toEqual({ F: { signal: "F" } });
  });

  it("builds the Tingen processor: F <- Input_F_in, chosen outputs in FMU order, typed parameters", () => {
    const choice = initialFmuChoice("Tingen.fmu", variables, ["Input_F_in"]);
    choice.feeds.F = { signal: "Input_F_in", scale: 0.5 };
    choice.outputs = ["sigma", "theta"];
    choice.parameters = { zeta: "0.7", L: "", tip_mass: " 1e-3 " };
    expect(buildFmuParts(choice)).toEqual({
      inputs: { F: { signal: "Input_F_in", scale: 0.5, offset: 0 } },
      params: { fmu: "Tingen.fmu", outputs: ["theta", "sigma"], parameters: { zeta: 0.7, tip_mass: 0.001 } },
      problems: {},
    });
  });

  it("names unfed inputs and reports what cannot be sent", () => {
    const choice = initialFmuChoice("Tingen.fmu", variables, []);
    choice.outputs = [];
    choice.parameters = { zeta: "much" };
    const parts = buildFmuParts(choice);
    expect(parts.inputs).toEqual({});
    expect(parts.params.inputs).toEqual([]); // F is not fed: only the listed inputs are
    expect(parts.problems).toEqual({
      "params.parameters": "Not a value of the variable's type: zeta.",
      "params.outputs": "Choose at least one output.",
    });
  });
});

describe("the body of POST .../processors", () => {
  it("merges the FMU parts with the other FMU settings and leaves defaults out", () => {
    const choice = initialFmuChoice("Tingen.fmu", variables, ["Input_F_in"]);
    choice.feeds.F = { signal: "Input_F_in" };
    const { spec, problems } = buildSpec(draft({ fmu: choice, params: { step: "fixed", step_size_s: 0.01 } }));
    expect(problems).toEqual({});
    expect(spec).toEqual({
      name: "fmu",
      blueprint: "fmu",
      source: "telemetry",
      enabled: true,
      inputs: { F: { signal: "Input_F_in", scale: 1, offset: 0 } },
      params: { step: "fixed", step_size_s: 0.01, fmu: "Tingen.fmu", outputs: ["theta", "sigma", "w"] },
    });
  });

  it("takes other blueprints' input rows, rates and limits", () => {
    const { spec } = buildSpec(
      draft({
        name: " smooth ",
        blueprint: "lowpass",
        output: "angle-smooth",
        enabled: false,
        params: { signals: ["a"], cutoff_hz: 3, sample_rate_hz: 100 },
        inputs: [{ input: "a", signal: "Cantilever_Angle_radians", offset: -0.1 }, { input: "", signal: "x" }],
        limits: { rates: { max_batch: 500, min_input_spacing_s: undefined }, memory_limit_mb: 256 },
      }),
    );
    expect(spec).toEqual({
      name: "smooth",
      blueprint: "lowpass",
      source: "telemetry",
      output: "angle-smooth",
      enabled: false,
      inputs: { a: { signal: "Cantilever_Angle_radians", scale: 1, offset: -0.1 } },
      params: { signals: ["a"], cutoff_hz: 3, sample_rate_hz: 100 },
      rates: { max_batch: 500 },
      memory_limit_mb: 256,
    });
  });

  it("asks for a name and an FMU before sending", () => {
    expect(buildSpec(draft({ name: "" })).problems).toEqual({ name: "Give the processor a name.", "params.fmu": "Choose an FMU." });
  });

  it("finds a free name", () => {
    expect(freeName("fmu", [])).toBe("fmu");
    expect(freeName("fmu", ["fmu", "fmu-2"])).toBe("fmu-3");
    expect(freeName("My Filter", [])).toBe("my-filter");
  });
});
