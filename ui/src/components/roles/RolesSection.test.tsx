import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { RolesSection } from "./RolesSection";

afterEach(() => {
  vi.unstubAllGlobals();
  vi.restoreAllMocks();
});

describe("RolesSection", () => {
  it("grants a role and takes one away", async () => {
    vi.spyOn(window, "confirm").mockReturnValue(true);
    let roles = [{ username: "admin", role: "owner" }, { username: "carol", role: "viewer" }];
    const fetch = mockFetch((_url, init) => {
      if (init?.method === "PUT") roles = [...roles, { username: "dave", role: "editor" }];
      if (init?.method === "DELETE") roles = roles.filter((r) => r.username !== "carol");
      return jsonResponse({ roles });
    });
    render(<RolesSection slug="tingen" role="owner" />);
    await screen.findByText("carol");
    const form = screen.getByRole("form", { name: "Grant a role" });
    fireEvent.change(within(form).getByLabelText("Username"), { target: { value: "dave" } });
    fireEvent.change(within(form).getByLabelText("New role"), { target: { value: "editor" } });
    fireEvent.click(within(form).getByRole("button", { name: "Grant" }));
    expect(await screen.findByText("dave")).toBeInTheDocument();
    const put = fetch.mock.calls.find(([, i]) => i?.method === "PUT")!;
    expect(put[0]).toBe("/api/v1/twins/tingen/roles/dave");
    expect(JSON.parse(String(put[1]?.body))).toEqual({ role: "editor" });

    fireEvent.click(within(screen.getByText("carol").closest("tr")!).getByRole("button", { name: "Remove" }));
    await vi.waitFor(() => expect(screen.queryByText("carol")).not.toBeInTheDocument());
    expect(fetch.mock.calls.some(([u, i]) => u === "/api/v1/twins/tingen/roles/carol" && i?.method === "DELETE")).toBe(true);
  });

  it("shows the refusal to take away the last owner", async () => {
    vi.spyOn(window, "confirm").mockReturnValue(true);
    mockFetch((_url, init) =>
      init?.method === "DELETE"
        ? problem(409, "'tingen' would have no owner left; grant another owner first")
        : jsonResponse({ roles: [{ username: "admin", role: "owner" }] }),
    );
    render(<RolesSection slug="tingen" role="admin" />);
    fireEvent.click(await screen.findByRole("button", { name: "Remove" }));
    const alert = await screen.findByRole("alert");
    expect(alert).toHaveTextContent("(409)");
    expect(alert).toHaveTextContent("no owner left");
    expect(screen.getByText("admin")).toBeInTheDocument();
  });

  it("changes a role with the select", async () => {
    const fetch = mockFetch(() => jsonResponse({ roles: [{ username: "carol", role: "viewer" }] }));
    render(<RolesSection slug="tingen" role="owner" />);
    fireEvent.change(await screen.findByLabelText("Role of carol"), { target: { value: "editor" } });
    await vi.waitFor(() => expect(fetch.mock.calls.some(([, i]) => i?.method === "PUT")).toBe(true));
  });

  it("shows nothing to editors and viewers", () => {
    const fetch = mockFetch(() => jsonResponse({ roles: [] }));
    const { container } = render(<RolesSection slug="tingen" role="editor" />);
    expect(container).toBeEmptyDOMElement();
    expect(fetch).not.toHaveBeenCalled();
  });
});
