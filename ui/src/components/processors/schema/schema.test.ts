import { describe, expect, it } from "vitest";
import type { JsonSchema } from "../../../api/processors";
import { fmuBlueprint, triggerBlueprint, windowBlueprint } from "../test/blueprints";
import { fieldKind, humanize, parseScalar, rangeText, resolve, schemaPaths, unwrap } from "./schema";

const trigger = triggerBlueprint.params_schema!;
const windowSchema = windowBlueprint.params_schema!;
const fmu = fmuBlueprint.params_schema!;

function kindOf(root: JsonSchema, key: string) {
  return fieldKind(unwrap(root.properties![key]!, root).schema, root);
}

describe("reading pydantic schemas", () => {
  it("resolves an optional $ref into $defs, keeping the outer description", () => {
    const { schema, nullable } = unwrap(trigger.properties!.command!, trigger);
    expect(nullable).toBe(true);
    expect(schema.description).toBe("A command to send on raising.");
    expect(Object.keys(schema.properties ?? {})).toEqual(["name", "params", "device"]);
    expect(schema.required).toEqual(["name"]);
  });

  it("merges allOf and keeps outer keywords on top", () => {
    const root: JsonSchema = { $defs: { Mode: { type: "string", enum: ["a", "b"], title: "Mode" } } };
    const merged = resolve({ allOf: [{ $ref: "#/$defs/Mode" }], default: "a", title: "Which mode" }, root);
    expect(merged).toMatchObject({ type: "string", enum: ["a", "b"], default: "a", title: "Which mode" });
  });

  it("unwraps optional numbers with their limits and old-style type lists", () => {
    const rate = unwrap(trigger.properties!.rate_limit!, trigger);
    expect(rate).toMatchObject({ nullable: true, schema: { type: "number", exclusiveMinimum: 0, default: null } });
    expect(unwrap({ type: ["integer", "null"] }, {})).toEqual({ schema: { type: "integer" }, nullable: true });
  });

  it("chooses an input for every kind of property", () => {
    expect(kindOf(trigger, "signal")).toBe("string");
    expect(kindOf(trigger, "mode")).toBe("enum");
    expect(kindOf(trigger, "high")).toBe("number");
    expect(kindOf(trigger, "command")).toBe("object");
    expect(kindOf(windowSchema, "signals")).toBe("stringArray");
    expect(kindOf(windowSchema, "functions")).toBe("enumArray");
    expect(kindOf(windowSchema, "window_samples")).toBe("integer");
    expect(kindOf(fmu, "parameters")).toBe("map");
    expect(kindOf(fmu, "outputs")).toBe("stringArray");
    const command = unwrap(trigger.properties!.command!, trigger).schema;
    expect(kindOf(command, "params")).toBe("json"); // free-form object: raw JSON
    expect(fieldKind({ type: "array", items: { type: "number" } }, {})).toBe("numberArray");
    expect(fieldKind({ type: "boolean" }, {})).toBe("boolean");
    expect(fieldKind({ type: "array", items: { type: "object" } }, {})).toBe("json");
  });

  it("lists every property path for placing server errors", () => {
    const paths = schemaPaths(trigger, trigger, "params");
    expect(paths).toContain("params");
    expect(paths).toContain("params.rate_limit");
    expect(paths).toContain("params.command.name");
    expect(paths).toContain("params.clear_command.device");
  });

  it("reads scalars, ranges and names", () => {
    expect(parseScalar("0.7", ["number", "integer", "boolean", "string"])).toBe(0.7);
    expect(parseScalar("true", ["number", "boolean", "string"])).toBe(true);
    expect(parseScalar("fast", ["number", "string"])).toBe("fast");
    expect(rangeText({ exclusiveMinimum: 0, maximum: 1 })).toBe("> 0, ≤ 1");
    expect(humanize("cutoff_hz")).toBe("Cutoff hz");
  });
});
