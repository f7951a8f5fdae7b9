import { describe, expect, it } from "vitest";
import { ApiError } from "../../api/client";
import { CHOOSE_DEVICE, forThisPage, preselectDevice } from "./deviceChoice";

const T = "2026-11-21T10:00:00Z";
const device = (name: string, connected = false) => ({ name, twin: "tingen", description: "", token_prefix: "tld_x", created: T, last_seen: null, connected });

describe("the device a command goes to", () => {
  it("preselects the server's choice, the declared default, the only connected, the only device", () => {
    const two = [device("rig", true), device("my-pi")];
    expect(preselectDevice(two, "my-pi", "rig")).toBe("rig");
    expect(preselectDevice(two, "my-pi")).toBe("my-pi");
    expect(preselectDevice(two, "gone")).toBe("rig"); // a declared default that is no device
    expect(preselectDevice(two, undefined, null)).toBe("rig");
    expect(preselectDevice([device("a"), device("b")], undefined)).toBeUndefined();
    expect(preselectDevice([device("a", true), device("b", true)], undefined)).toBeUndefined();
    expect(preselectDevice([device("only")], undefined)).toBe("only");
    expect(preselectDevice([], "x")).toBeUndefined();
  });

  it("speaks of the Device list, not of the API's field", () => {
    const server = new ApiError(422, "twin 'tingen' has several devices (a, b), its interface declares no `default_device`, and none of them are connected; name one with `device`");
    const phrased = forThisPage(server);
    expect(phrased.message).toBe(
      `twin 'tingen' has several devices (a, b), its interface declares no \`default_device\`, and none of them are connected. ${CHOOSE_DEVICE}`,
    );
    expect((phrased as ApiError).status).toBe(422);
    const other = new ApiError(404, "twin 'tingen' has no device 'x'");
    expect(forThisPage(other)).toBe(other);
  });
});
