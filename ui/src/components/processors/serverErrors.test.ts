import { describe, expect, it } from "vitest";
import { ApiError } from "../../api/client";
import { formErrors, matchPath, splitDetail } from "./serverErrors";

const known = new Set(["name", "source", "inputs", "rates", "rates.max_batch", "params", "params.cutoff_hz", "params.signals"]);

describe("placing server errors", () => {
  it("splits a blueprint's parameter errors into paths", () => {
    expect(splitDetail("params: cutoff_hz: Input should be greater than 0; signals: Field required")).toEqual([
      { path: "params.cutoff_hz", message: "Input should be greater than 0" },
      { path: "params.signals", message: "Field required" },
    ]);
    expect(splitDetail("a processor cannot write the stream it reads")).toEqual([{ path: null, message: "a processor cannot write the stream it reads" }]);
    expect(splitDetail("params: unknown FMU inputs: G (valid: F)")).toEqual([{ path: null, message: "unknown FMU inputs: G (valid: F)" }]);
  });

  it("matches the longest known path", () => {
    expect(matchPath("params.signals.0", known)).toBe("params.signals");
    expect(matchPath("inputs.F.InputMap.signal", known)).toBe("inputs");
    expect(matchPath("other", known)).toBeNull();
  });

  it("places a 422 detail at its field and the rest on top", () => {
    const err = new ApiError(422, "params: cutoff_hz: Input should be greater than 0");
    expect(formErrors(err, known)).toMatchObject({ fields: { "params.cutoff_hz": "Input should be greater than 0" }, general: null });
    const spec = new ApiError(422, "name: Value error, 'Bad Name' must be lowercase letters");
    expect(formErrors(spec, known).fields).toEqual({ name: "'Bad Name' must be lowercase letters" });
    const loop = new ApiError(422, "'fmu' -> 'telemetry' would make a loop of processors");
    expect(formErrors(loop, known)).toMatchObject({ fields: {}, general: "'fmu' -> 'telemetry' would make a loop of processors" });
  });

  it("uses errors[].path of a request that does not fit, and puts other statuses on top", () => {
    const problem = {
      detail: "The request is not valid: body.rates.max_batch: Input should be greater than or equal to 1",
      errors: [
        { path: "body.rates.max_batch", message: "Input should be greater than or equal to 1" },
        { path: "body.colour", message: "Extra inputs are not permitted" },
      ],
    };
    const err = new ApiError(422, problem.detail, problem);
    expect(formErrors(err, known)).toMatchObject({
      fields: { "rates.max_batch": "Input should be greater than or equal to 1" },
      general: "colour: Extra inputs are not permitted",
    });
    expect(formErrors(new ApiError(409, "the twin already has a processor 'fmu'"), known)).toMatchObject({
      fields: {},
      general: "the twin already has a processor 'fmu'",
    });
  });
});
