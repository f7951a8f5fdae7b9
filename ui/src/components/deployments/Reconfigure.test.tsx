import { afterEach, describe, expect, it, vi } from "vitest";
import { render, screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { setToken } from "../../api/client";
import type { Deployment } from "../../api/deployments";
import { jsonResponse, mockFetch } from "../../test/fetch";
import { parsePinned } from "./PackagePicker";
import { Reconfigure } from "./Reconfigure";

afterEach(() => vi.unstubAllGlobals());

const d1 = `sha256:${"1".repeat(64)}`;
const d2 = `sha256:${"2".repeat(64)}`;
const yaml = (max: number) => `parameters:
  type: object
  properties:
    capacity: {type: number, default: 2.5, minimum: 0.1, maximum: ${max}}
    medium: {enum: [water, oil], default: water}
`;
const deployment: Deployment = {
  id: 1, name: "tank-a", package: `lib:common/twins/ui-tank@${d1}`, package_ref: "ui-tank@1.0.0", parameters: { capacity: 4, medium: "oil" },
  state: "running", twin: "tank-a", resources: { twin: "tank-a", devices: ["level"], processors: [], connectors: [], services: [] }, created_by: "admin", created_ns: 0, updated_ns: 0, error: null,
};
const plan = { create: [], update: [{ type: "twin", name: "tank-a", changes: [{ path: "description", from: "oil tank of 4 m³", to: "oil tank of 5 m³" }] }], delete: [], keep: [{ type: "device", name: "level" }] };
const version = (digest: string, tags: string[]) => ({ digest, size: 1, file_count: 1, tags, meta: {}, created_ns: 0, created_by: "admin" });

function setup() {
  setToken("tl_x");
  const fetch = mockFetch((url, init) => {
    if (url === "/api/v1/library/common/twins/ui-tank") {
      return jsonResponse({ scope: "common", kind: "twins", name: "ui-tank", ref: "common/twins/ui-tank", tags: { latest: d2, "1.1.0": d2, "1.0.0": d1 }, versions: [version(d2, ["1.1.0", "latest"]), version(d1, ["1.0.0"])] });
    }
    if (url === `/api/v1/library/common/twins/ui-tank/versions/${encodeURIComponent(d1)}/files/twin.yaml`) return new Response(yaml(10));
    if (url === "/api/v1/library/common/twins/ui-tank/versions/1.1.0/files/twin.yaml") return new Response(yaml(20));
    if (url.startsWith("/api/v1/deployments/tank-a") && init?.method === "PATCH") return jsonResponse({ deployment, plan, device_tokens: {} });
    return jsonResponse({ detail: `unexpected ${url}` }, 404);
  });
  const onDone = vi.fn();
  render(<Reconfigure deployment={deployment} onDone={onDone} onCancel={() => undefined} />);
  const patches = () =>
    fetch.mock.calls.filter(([, i]) => i?.method === "PATCH").map(([u, i]) => [String(u), JSON.parse(String(i!.body)) as unknown]);
  return { onDone, patches };
}

describe("Reconfigure", () => {
  it("starts from the values the deployment runs with, plans the change, then applies it", async () => {
    const { onDone, patches } = setup();
    const capacity = await screen.findByLabelText("Capacity");
    expect(capacity).toHaveValue(4);
    expect(screen.getByLabelText("Medium")).toHaveDisplayValue("oil");
    await userEvent.clear(capacity);
    await userEvent.type(capacity, "5");
    await userEvent.click(screen.getByRole("button", { name: "Plan changes" }));
    const shown = await screen.findByRole("region", { name: "Plan" });
    expect(within(shown).getByText("description").parentElement).toHaveTextContent("description: oil tank of 4 m³ → oil tank of 5 m³");
    await userEvent.click(screen.getByRole("button", { name: "Apply" }));
    await vi.waitFor(() => expect(onDone).toHaveBeenCalledOnce());
    const body = { parameters: { capacity: 5, medium: "oil" } };
    expect(patches()).toEqual([
      ["/api/v1/deployments/tank-a?dry_run=true", body],
      ["/api/v1/deployments/tank-a", body],
    ]);
  });

  it("moves to another version of the package, with that version's form", async () => {
    const { patches } = setup();
    const capacity = await screen.findByLabelText("Capacity");
    const picker = screen.getByLabelText("Version");
    await vi.waitFor(() => expect(within(picker).getByRole("option", { name: /^1\.1\.0/ })).toBeInTheDocument());
    expect(picker).toHaveValue(d1);
    await userEvent.selectOptions(picker, "1.1.0");
    await vi.waitFor(() => expect(screen.getByText(/Allowed: ≥ 0.1, ≤ 20/)).toBeInTheDocument());
    await userEvent.clear(capacity);
    await userEvent.type(capacity, "15");
    await userEvent.click(screen.getByRole("button", { name: "Plan changes" }));
    await screen.findByRole("region", { name: "Plan" });
    expect(patches()).toEqual([["/api/v1/deployments/tank-a?dry_run=true", { parameters: { capacity: 15, medium: "oil" }, package: "common/twins/ui-tank@1.1.0" }]]);
  });

  it("reads a pinned package reference", () => {
    expect(parsePinned(`lib:group:ntnu/twins/rig@${d1}`)).toEqual({ scope: "group:ntnu", kind: "twins", name: "rig", version: d1 });
    expect(parsePinned("rig@1.0.0")).toBeNull();
  });
});
