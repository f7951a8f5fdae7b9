import { describe, expect, it } from "vitest";
import { checkParameters, parameterDefaults, parseTwinYaml } from "./packageParams";

const TWIN_YAML = `
description: The Tingen cantilever rig with its FMU
parameters:
  type: object
  properties:
    zeta: {type: number, default: 0.7, minimum: 0, maximum: 2, description: damping ratio}
    steps: {type: integer, default: 10, exclusiveMinimum: 0}
    mode: {enum: [fast, exact], default: exact}
    live: {type: boolean, default: true}
    label: {type: string, minLength: 2}
  required: [label]
  additionalProperties: false
document: document.yaml
processors:
  - name: fmu
    params: {parameters: {zeta: "\${params.zeta}"}}
`;

describe("parseTwinYaml", () => {
  it("reads the description and the parameters' schema of a package", () => {
    const info = parseTwinYaml(TWIN_YAML);
    expect(info.description).toBe("The Tingen cantilever rig with its FMU");
    expect(Object.keys(info.parameters?.properties ?? {})).toEqual(["zeta", "steps", "mode", "live", "label"]);
    expect(info.parameters?.properties?.zeta).toEqual({ type: "number", default: 0.7, minimum: 0, maximum: 2, description: "damping ratio" });
  });

  it("answers no schema for a package without parameters, or an empty twin.yaml", () => {
    expect(parseTwinYaml("document: document.yaml\n").parameters).toBeNull();
    expect(parseTwinYaml("")).toEqual({ description: null, parameters: null });
  });

  it("names what is wrong with a twin.yaml that is not a package description", () => {
    expect(() => parseTwinYaml("parameters: [a, b]\n")).toThrow("`parameters` must be a JSON schema of an object");
    expect(() => parseTwinYaml("parameters: {type: array}\n")).toThrow("must describe an object, not a array");
    expect(() => parseTwinYaml("- one\n- two\n")).toThrow("twin.yaml must be a mapping");
    expect(() => parseTwinYaml("parameters: {type: object\n")).toThrow("twin.yaml is not valid YAML: unexpected end of the stream within a flow collection (line 2, column 1)");
  });
});

describe("parameterDefaults", () => {
  it("starts the form from every property's default, and from nothing where none is given", () => {
    expect(parameterDefaults(parseTwinYaml(TWIN_YAML).parameters)).toEqual({ zeta: 0.7, steps: 10, mode: "exact", live: true });
    expect(parameterDefaults(null)).toEqual({});
  });

  it("copies defaults that are objects, so editing the form does not change the schema", () => {
    const schema = { type: "object", properties: { gains: { type: "object", default: { p: 1 } } } };
    const values = parameterDefaults(schema);
    (values.gains as Record<string, number>).p = 2;
    expect(schema.properties.gains.default).toEqual({ p: 1 });
  });
});

describe("checkParameters", () => {
  const schema = parseTwinYaml(TWIN_YAML).parameters;

  it("passes values that fit the schema", () => {
    expect(checkParameters(schema, { zeta: 2, steps: 1, mode: "fast", live: false, label: "ok" })).toEqual({});
  });

  it("places each broken limit at its field's path", () => {
    expect(checkParameters(schema, { zeta: 2.5, steps: 0, mode: "slow", live: "yes", label: "x" })).toEqual({
      "parameters.zeta": "must be ≥ 0, ≤ 2",
      "parameters.steps": "must be > 0",
      "parameters.mode": "must be one of fast, exact",
      "parameters.live": "must be true or false",
      "parameters.label": "must be at least 2 characters",
    });
    expect(checkParameters(schema, { steps: 1.5, label: "ab" })).toEqual({ "parameters.steps": "must be a whole number" });
  });

  it("asks for a required value without a default", () => {
    expect(checkParameters(schema, {})).toEqual({ "parameters.label": "is required" });
  });
});
