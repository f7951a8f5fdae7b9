import { afterEach, describe, expect, it, vi } from "vitest";
import { render, screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { MemoryRouter } from "react-router-dom";
import { setToken } from "../api/client";
import { jsonResponse, mockFetch, problem } from "../test/fetch";
import { DeploymentsPage } from "./DeploymentsPage";

afterEach(() => vi.unstubAllGlobals());

const deployment = (name: string, state: string) => ({
  id: 1, name, package: "lib:common/twins/rig@sha256:1", package_ref: "rig@1.0.0", parameters: {}, state, twin: name,
  resources: { twin: name, devices: [], processors: [], connectors: [], services: [] }, created_by: "ann", created_ns: 1.7e18, updated_ns: 1.7e18, error: null,
});

function renderWith(answer: () => Response) {
  setToken("tl_x");
  mockFetch((url) => (url === "/api/v1/deployments" ? answer() : url.startsWith("/api/v1/library?") ? jsonResponse({ assets: [] }) : problem(404, url)));
  render(
    <MemoryRouter future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <DeploymentsPage />
    </MemoryRouter>,
  );
}

describe("DeploymentsPage", () => {
  it("lists the deployments with their states, linked to their pages and twins", async () => {
    renderWith(() => jsonResponse({ deployments: [deployment("rig-a", "running"), deployment("rig-b", "terminated")] }));
    const table = await screen.findByRole("table", { name: "Deployments" });
    const [, a, b] = within(table).getAllByRole("row");
    expect(within(a!).getByText("running")).toHaveClass("dep-state-running");
    expect(within(a!).getAllByRole("link").map((l) => l.getAttribute("href"))).toEqual(["/deployments/rig-a", "/twins/rig-a"]);
    // A terminated deployment's twin may be gone: named, not linked.
    expect(within(b!).getAllByRole("link").map((l) => l.getAttribute("href"))).toEqual(["/deployments/rig-b"]);
  });

  it("says what to do when there is none, and offers the form", async () => {
    renderWith(() => jsonResponse({ deployments: [] }));
    expect(await screen.findByText(/No deployment yet/)).toBeInTheDocument();
    await userEvent.click(screen.getByRole("button", { name: "New deployment" }));
    expect(screen.getByRole("form", { name: "New deployment" })).toBeInTheDocument();
    expect(await screen.findByText(/There is no twin package in the library you may read/)).toBeInTheDocument();
  });

  it("shows the problem when the list cannot be read", async () => {
    renderWith(() => problem(503, "deployments are not set up on this server"));
    expect(await screen.findByRole("alert")).toHaveTextContent("(503): deployments are not set up on this server");
  });
});
