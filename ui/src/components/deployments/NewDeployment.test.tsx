import { afterEach, describe, expect, it, vi } from "vitest";
import { render, screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { setToken } from "../../api/client";
import { jsonResponse, mockFetch } from "../../test/fetch";
import { NewDeployment } from "./NewDeployment";

afterEach(() => vi.unstubAllGlobals());

const TWIN_YAML = `description: The Tingen rig
parameters:
  type: object
  properties:
    zeta: {type: number, default: 0.7, minimum: 0, maximum: 2, description: damping ratio}
    mode: {enum: [fast, exact], default: exact}
    live: {type: boolean, default: true, description: stream while running}
`;
const digest = `sha256:${"ab".repeat(32)}`;
const asset = {
  scope: "common", kind: "twins", name: "tingen-rig", ref: "common/twins/tingen-rig", description: "The rig",
  keywords: [], licence: null, author: null, tags: { latest: digest, "1.0.0": digest }, latest: digest, versions: 1, updated_ns: 1e18,
};
const plan = { create: [{ type: "twin", name: "tingen-rig" }, { type: "processor", name: "fmu", spec: { params: { parameters: { zeta: 1.2 } } } }], update: [], delete: [], keep: [] };

function setup(deployAnswer: () => Response = () => jsonResponse({ deployment: { name: "tingen-rig" }, plan, device_tokens: {} }, 201)) {
  setToken("tl_x");
  const fetch = mockFetch((url, init) => {
    if (url.startsWith("/api/v1/library?")) return jsonResponse({ assets: [asset] });
    if (url === "/api/v1/library/common/twins/tingen-rig") return jsonResponse({ ...asset, versions: [{ digest, size: 10, tags: ["1.0.0", "latest"], meta: {}, created_ns: 1e18, created_by: "admin" }] });
    if (url === "/api/v1/library/common/twins/tingen-rig/versions/latest/files/twin.yaml") return new Response(TWIN_YAML, { headers: { "Content-Type": "application/yaml" } });
    if (url === "/api/v1/deployments?dry_run=true" && init?.method === "POST") return jsonResponse({ plan });
    if (url === "/api/v1/deployments" && init?.method === "POST") return deployAnswer();
    return jsonResponse({ detail: `unexpected ${url}` }, 404);
  });
  const onCreated = vi.fn();
  render(<NewDeployment onCreated={onCreated} onCancel={() => undefined} />);
  return { fetch, onCreated };
}

const bodies = (fetch: ReturnType<typeof mockFetch>, url: string) =>
  fetch.mock.calls.filter(([u, init]) => String(u) === url && init?.method === "POST").map(([, init]) => JSON.parse(String(init!.body)) as unknown);

describe("NewDeployment", () => {
  it("generates the parameter form from the package's twin.yaml, with labels, defaults and limits", async () => {
    setup();
    await userEvent.selectOptions(await screen.findByLabelText("Twin package"), "common/twins/tingen-rig");
    const zeta = await screen.findByLabelText("Zeta");
    expect(zeta).toHaveValue(0.7);
    expect(zeta).toHaveAttribute("min", "0");
    expect(zeta).toHaveAttribute("max", "2");
    expect(screen.getByText("damping ratio Default: 0.7. Allowed: ≥ 0, ≤ 2.")).toBeInTheDocument();
    expect(screen.getByLabelText("Mode")).toHaveDisplayValue("exact");
    expect(screen.getByLabelText("Live")).toBeChecked();
    expect(screen.getByLabelText("Name")).toHaveValue("tingen-rig");
    expect(screen.getByLabelText("Version")).toHaveValue("latest");
  });

  it("plans with the values typed, then deploys exactly that", async () => {
    const { fetch, onCreated } = setup();
    await userEvent.selectOptions(await screen.findByLabelText("Twin package"), "common/twins/tingen-rig");
    const zeta = await screen.findByLabelText("Zeta");
    await userEvent.clear(zeta);
    await userEvent.type(zeta, "1.2");
    await userEvent.click(screen.getByLabelText("Live"));
    await userEvent.click(screen.getByRole("button", { name: "Plan" }));
    const shown = await screen.findByRole("region", { name: "Plan" });
    expect(within(shown).getByText(/2 to create/)).toBeInTheDocument();
    const request = { package: "common/twins/tingen-rig@latest", name: "tingen-rig", parameters: { zeta: 1.2, mode: "exact", live: false } };
    expect(bodies(fetch, "/api/v1/deployments?dry_run=true")).toEqual([request]);
    expect(bodies(fetch, "/api/v1/deployments")).toEqual([]);
    await userEvent.click(screen.getByRole("button", { name: "Deploy" }));
    await vi.waitFor(() => expect(onCreated).toHaveBeenCalledOnce());
    expect(bodies(fetch, "/api/v1/deployments")).toEqual([{ ...request, start: true }]);
  });

  it("asks for a new plan once a value changed", async () => {
    setup();
    await userEvent.selectOptions(await screen.findByLabelText("Twin package"), "common/twins/tingen-rig");
    await screen.findByLabelText("Zeta");
    await userEvent.click(screen.getByRole("button", { name: "Plan" }));
    await screen.findByRole("region", { name: "Plan" });
    await userEvent.type(screen.getByLabelText("Name"), "-2");
    expect(screen.queryByRole("region", { name: "Plan" })).toBeNull();
    expect(screen.getByRole("button", { name: "Plan" })).toBeInTheDocument();
  });

  it("refuses a value out of its limits before sending anything, at the field", async () => {
    const { fetch } = setup();
    await userEvent.selectOptions(await screen.findByLabelText("Twin package"), "common/twins/tingen-rig");
    const zeta = await screen.findByLabelText("Zeta");
    await userEvent.clear(zeta);
    await userEvent.type(zeta, "3");
    await userEvent.click(screen.getByRole("button", { name: "Plan" }));
    expect(await screen.findByText("must be ≥ 0, ≤ 2")).toBeInTheDocument();
    expect(bodies(fetch, "/api/v1/deployments?dry_run=true")).toEqual([]);
    // Changed, the value is no longer marked.
    await userEvent.clear(zeta);
    await userEvent.type(zeta, "1");
    expect(screen.queryByText("must be ≥ 0, ≤ 2")).toBeNull();
  });

  it("places the deployments API's 'parameter NAME: message' at that field", async () => {
    setup(() => jsonResponse({ title: "Invalid input", status: 422, detail: "parameter mode: 'slow' is not one of ['fast', 'exact']" }, 422, "application/problem+json"));
    await userEvent.selectOptions(await screen.findByLabelText("Twin package"), "common/twins/tingen-rig");
    await screen.findByLabelText("Zeta");
    await userEvent.click(screen.getByRole("button", { name: "Plan" }));
    await screen.findByRole("region", { name: "Plan" });
    await userEvent.click(screen.getByRole("button", { name: "Deploy" }));
    const message = await screen.findByText("'slow' is not one of ['fast', 'exact']");
    expect(message.closest("[data-path]")).toHaveAttribute("data-path", "parameters.mode");
    expect(screen.queryByRole("alert")).toBeNull();
  });

  it("shows the server's problem at the field it names, and the rest above the form", async () => {
    setup(() =>
      jsonResponse(
        { title: "Invalid input", status: 422, detail: "parameters.mode: must be fast or exact; the name tingen-rig is taken" },
        422,
        "application/problem+json",
      ),
    );
    await userEvent.selectOptions(await screen.findByLabelText("Twin package"), "common/twins/tingen-rig");
    await screen.findByLabelText("Zeta");
    await userEvent.click(screen.getByRole("button", { name: "Plan" }));
    await screen.findByRole("region", { name: "Plan" });
    await userEvent.click(screen.getByRole("button", { name: "Deploy" }));
    expect(await screen.findByText("must be fast or exact")).toBeInTheDocument();
    expect(screen.getByRole("alert")).toHaveTextContent("the name tingen-rig is taken");
  });
});
