import { afterEach, describe, expect, it, vi } from "vitest";
import { render, screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { setToken } from "../../api/client";
import { jsonResponse, mockFetch } from "../../test/fetch";
import { WorkspaceLink } from "./WorkspaceLink";

afterEach(() => vi.unstubAllGlobals());

function fakeTab() {
  return { opener: {} as unknown, location: { href: "about:blank" }, close: vi.fn() };
}

describe("WorkspaceLink", () => {
  it("starts the workspace and sends a new tab, cut off from this one, to its one-time link", async () => {
    setToken("tl_x");
    const fetch = mockFetch(() => jsonResponse({ user: "ann", state: "running", url: "/workspaces/ann/?ticket=t1", log: [] }));
    const tab = fakeTab();
    const open = vi.spyOn(window, "open").mockReturnValue(tab as unknown as Window);
    render(<WorkspaceLink />);
    await userEvent.click(screen.getByRole("button", { name: "Workspace" }));
    await vi.waitFor(() => expect(tab.location.href).toBe("/workspaces/ann/?ticket=t1"));
    expect(open).toHaveBeenCalledWith("about:blank", "_blank");
    expect(tab.opener).toBeNull();
    expect(fetch).toHaveBeenCalledWith("/api/v1/workspaces/me", expect.objectContaining({ method: "POST" }));
  });

  it("closes the tab and says why when the workspace does not run", async () => {
    setToken("tl_x");
    mockFetch(() => jsonResponse({ user: "ann", state: "failed", url: null, error: "jupyter lab exited with 1", log: [] }));
    const tab = fakeTab();
    vi.spyOn(window, "open").mockReturnValue(tab as unknown as Window);
    render(<WorkspaceLink />);
    await userEvent.click(screen.getByRole("button", { name: "Workspace" }));
    expect(await screen.findByRole("alert")).toHaveTextContent("The workspace did not start: it is failed: jupyter lab exited with 1");
    expect(tab.close).toHaveBeenCalled();
  });
});
