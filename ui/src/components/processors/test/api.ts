// A fake processor API for component tests: answers like the server's routes.
import type { Processor } from "../../../api/processors";
import { jsonResponse } from "../../../test/fetch";
import { fmuBlueprint, lowpassBlueprint, triggerBlueprint, windowBlueprint } from "./blueprints";
import { tingenFmu } from "./tingen";

export const blueprints = [fmuBlueprint, lowpassBlueprint, triggerBlueprint, windowBlueprint];

export const streams = {
  twin: "tingen",
  streams: [
    {
      name: "telemetry",
      count: 2000,
      first: 1,
      last: 2,
      signals: [
        { name: "Cantilever_Angle_radians", kind: "number", count: 1000, first: 1, last: 2 },
        { name: "Input_F_in", kind: "number", count: 1000, first: 1, last: 2 },
      ],
    },
  ],
};

export function processor(change: Partial<Processor> = {}): Processor {
  return {
    name: "fmu",
    twin: "tingen",
    blueprint: "fmu",
    source: "telemetry",
    output: null,
    inputs: { F: { signal: "Input_F_in", scale: 1, offset: 0 } },
    params: { fmu: "Tingen.fmu", outputs: ["theta", "sigma"] },
    rates: { min_input_spacing_s: 0, min_step_spacing_s: 0, min_output_spacing_s: 0, max_batch: 10000 },
    memory_limit_mb: 1024,
    batch_timeout_s: 30,
    enabled: true,
    state: "running",
    pid: 4242,
    last_error: null,
    restart_at: null,
    stats: {
      samples_in: 1520,
      samples_out: 1519,
      batches: 12,
      dropped: 3,
      restarts: 0,
      crashes: 0,
      rss_bytes: 47_395_635,
      step_time_s: { p50: 0.0000123, p99: 0.0000456 },
      added_latency_s: { p50: 0.00123, p99: 0.0042 },
    },
    running: { inputs: ["F"], outputs: ["theta", "sigma"], describe: { model_name: "tingen" } },
    created_ns: 1_767_225_600_000_000_000,
    modified_ns: 1_767_225_600_000_000_000,
    ...change,
  };
}

/** Answers of the read-only routes; `extra` answers first (writes, special cases). */
export function fakeApi(extra: (url: string, init?: RequestInit) => Response | null = () => null) {
  return (url: string, init?: RequestInit): Response => {
    const special = extra(url, init);
    if (special) return special;
    const bp = /^\/api\/v1\/blueprints\/([^/?]+)$/.exec(url);
    if (bp) return jsonResponse(blueprints.find((b) => b.name === bp[1]));
    if (url === "/api/v1/blueprints") return jsonResponse({ blueprints });
    if (url.endsWith("/streams")) return jsonResponse(streams);
    if (url.endsWith("/fmus")) return jsonResponse({ fmus: [{ ...tingenFmu, variables: undefined }] });
    if (url.endsWith("/fmus/Tingen.fmu")) return jsonResponse(tingenFmu);
    return jsonResponse({ detail: `no fake answer for ${url}` }, 404);
  };
}
