import { describe, expect, it } from "vitest";
import { load } from "js-yaml";
import { aliasFor, cartRef, twinYamlFor } from "./cart";

describe("the package cart", () => {
  it("writes a twin.yaml naming each asset under its alias, with a document template", () => {
    const text = twinYamlFor(
      [
        { alias: "beam", ref: "lib:common/models/tingen-beam@latest" },
        { alias: "sim", ref: `lib:group:ntnu/tools/tingen-sim@sha256:${"a".repeat(64)}` },
      ],
      'The rig: "Tingen" #1',
    );
    expect(load(text)).toEqual({
      description: 'The rig: "Tingen" #1',
      assets: { beam: "lib:common/models/tingen-beam@latest", sim: `lib:group:ntnu/tools/tingen-sim@sha256:${"a".repeat(64)}` },
      document: { version: "1.0", name: "${deployment.name}", description: 'The rig: "Tingen" #1' },
    });
    expect(load(twinYamlFor([], ""))).not.toHaveProperty("assets");
  });

  it("makes aliases templates can name, each once", () => {
    expect(aliasFor("tingen-beam", [])).toBe("tingen_beam");
    expect(aliasFor("tingen-beam", ["tingen_beam"])).toBe("tingen_beam_2");
    expect(aliasFor("2d.model", [])).toBe("d_model");
    expect(aliasFor("---", [])).toBe("asset");
  });

  it("names an asset by its latest tag, else by its newest version", () => {
    expect(cartRef({ ref: "common/data/x", tags: { latest: "sha256:1" }, latest: "sha256:1" })).toBe("lib:common/data/x@latest");
    expect(cartRef({ ref: "common/data/x", tags: {}, latest: "sha256:2" })).toBe("lib:common/data/x@sha256:2");
  });
});
