import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import type { TokenInfo, User } from "../api/admin";
import { getToken, setToken } from "../api/client";
import { AuthProvider } from "../auth/AuthContext";
import { jsonResponse, mockFetch, problem } from "../test/fetch";
import { AdminPage } from "./AdminPage";

afterEach(() => {
  vi.unstubAllGlobals();
  vi.restoreAllMocks();
});

const T = "2026-11-21T10:00:00.000Z";
const SECRET = "tl_SuperSecretValue0123456789abcdefghijklmnopq";
const alice: User = { username: "alice", is_admin: false, groups: ["group-1"], disabled: false, created: T };
const root: User = { username: "root", is_admin: true, groups: [], disabled: false, created: T };
const session: TokenInfo = { id: 1, name: "login session", state: "active", prefix: "tl_Sessio", kind: "session", created: T, expires: T, last_used: T, revoked: null, username: "alice", current: true };
const ci: TokenInfo = { id: 6, name: "ci", state: "active", prefix: "tl_SuperS", kind: "api", created: T, expires: null, last_used: null, revoked: null, username: "alice", current: false };

function fillPasswordForm(form: HTMLElement, current: string, next: string) {
  fireEvent.change(within(form).getByLabelText("Current password"), { target: { value: current } });
  fireEvent.change(within(form).getByLabelText("New password"), { target: { value: next } });
  fireEvent.change(within(form).getByLabelText("Repeat the new password"), { target: { value: next } });
}

function renderPage() {
  setToken("tl_SessionToken");
  return render(
    <AuthProvider>
      <AdminPage />
    </AuthProvider>,
  );
}

describe("AdminPage", () => {
  it("creates a token and shows its secret once, never in the list or storage", async () => {
    let tokens = [session];
    const fetch = mockFetch((url, init) => {
      if (url === "/api/v1/auth/me") return jsonResponse(alice);
      if (url === "/api/v1/tokens" && init?.method === "POST") {
        tokens = [session, ci];
        return jsonResponse({ token: SECRET, ...ci }, 201);
      }
      return jsonResponse({ tokens });
    });
    renderPage();
    expect(await screen.findByText("this session")).toBeInTheDocument();
    const form = screen.getByRole("form", { name: "Create a token" });
    fireEvent.change(within(form).getByLabelText("Token name"), { target: { value: "ci" } });
    fireEvent.change(within(form).getByLabelText("Expires"), { target: { value: "2" } });
    fireEvent.click(within(form).getByRole("button", { name: "Create token" }));
    expect(await screen.findByTestId("secret-value")).toHaveValue(SECRET);
    const post = fetch.mock.calls.find(([, i]) => i?.method === "POST")!;
    expect(JSON.parse(String(post[1]?.body))).toEqual({ name: "ci", expires_in_s: 7 * 86_400 });
    const table = await screen.findByTestId("token-table");
    await within(table).findByText("ci");
    expect(table.innerHTML).not.toContain(SECRET);
    expect(JSON.stringify({ ...sessionStorage, ...localStorage })).not.toContain(SECRET);
    fireEvent.click(screen.getByRole("button", { name: "I have saved it" }));
    expect(screen.queryByTestId("secret-value")).not.toBeInTheDocument();
    expect(document.body.innerHTML).not.toContain(SECRET);
  });

  it("does not show the users section to a non-admin", async () => {
    const fetch = mockFetch((url) => (url === "/api/v1/auth/me" ? jsonResponse(alice) : jsonResponse({ tokens: [] })));
    renderPage();
    expect(await screen.findByRole("heading", { name: "Account" })).toBeInTheDocument();
    expect(screen.getByText("group-1")).toBeInTheDocument();
    expect(await screen.findByText("No tokens.")).toBeInTheDocument();
    expect(screen.queryByRole("heading", { name: "Users" })).not.toBeInTheDocument();
    expect(screen.queryByRole("heading", { name: "All tokens" })).not.toBeInTheDocument();
    expect(fetch.mock.calls.some(([url]) => String(url).startsWith("/api/v1/users"))).toBe(false);
  });

  it("lets an admin create a user", async () => {
    let users = [root];
    const fetch = mockFetch((url, init) => {
      if (url === "/api/v1/auth/me") return jsonResponse(root);
      if (url === "/api/v1/users" && init?.method === "POST") {
        users = [root, { ...alice, username: "bob", groups: ["group-1", "ops"] }];
        return jsonResponse(users[1], 201);
      }
      if (url === "/api/v1/users") return jsonResponse({ users });
      return jsonResponse({ tokens: [] });
    });
    renderPage();
    expect(await screen.findByRole("heading", { name: "Admin" })).toBeInTheDocument();
    expect(await screen.findByRole("heading", { name: "All tokens" })).toBeInTheDocument();
    const form = screen.getByRole("form", { name: "Create a user" });
    fireEvent.change(within(form).getByLabelText("Username"), { target: { value: "bob" } });
    fireEvent.change(within(form).getByLabelText("Password (optional)"), { target: { value: "bobpassword1" } });
    fireEvent.change(within(form).getByLabelText("Groups"), { target: { value: "group-1, ops" } });
    fireEvent.click(within(form).getByRole("button", { name: "Create user" }));
    expect(await screen.findByLabelText("Groups of bob")).toHaveValue("group-1, ops");
    const post = fetch.mock.calls.find(([, i]) => i?.method === "POST")!;
    expect(JSON.parse(String(post[1]?.body))).toEqual({ username: "bob", password: "bobpassword1", is_admin: false, groups: ["group-1", "ops"] });
    expect(fetch.mock.calls.some(([url]) => String(url) === "/api/v1/tokens?all=true")).toBe(true);
  });

  it("lets an admin disable a user and give them a token", async () => {
    const fetch = mockFetch((url, init) => {
      if (url === "/api/v1/auth/me") return jsonResponse(root);
      if (url === "/api/v1/users/alice" && init?.method === "PATCH") return jsonResponse({ ...alice, disabled: true });
      if (url === "/api/v1/users/alice/tokens") return jsonResponse({ token: SECRET, ...ci, username: "alice" }, 201);
      if (url === "/api/v1/users") return jsonResponse({ users: [root, alice] });
      return jsonResponse({ tokens: [] });
    });
    renderPage();
    fireEvent.click(await screen.findByLabelText("alice is disabled"));
    fireEvent.click(within(screen.getByText("alice").closest("tr")!).getByRole("button", { name: "Save" }));
    await vi.waitFor(() => expect(fetch.mock.calls.some(([, i]) => i?.method === "PATCH")).toBe(true));
    const patch = fetch.mock.calls.find(([, i]) => i?.method === "PATCH")!;
    expect(JSON.parse(String(patch[1]?.body))).toEqual({ disabled: true });

    const tokenButton = within(screen.getByText("alice").closest("tr")!).getByRole("button", { name: "Token…" });
    await vi.waitFor(() => expect(tokenButton).toBeEnabled());
    fireEvent.click(tokenButton);
    const form = screen.getByRole("form", { name: "Create a token for alice" });
    fireEvent.change(within(form).getByLabelText("Token name"), { target: { value: "ingest" } });
    fireEvent.click(within(form).getByRole("button", { name: "Create token" }));
    expect(await screen.findByTestId("secret-value")).toHaveValue(SECRET);
    expect(screen.getByText(/of alice/)).toBeInTheDocument();
  });

  it("changes the own password with the current one and says the session has ended", async () => {
    const fetch = mockFetch((url, init) => {
      if (url === "/api/v1/auth/me") return jsonResponse(alice);
      if (init?.method === "PATCH") return jsonResponse(alice);
      return jsonResponse({ tokens: [] });
    });
    renderPage();
    const form = await screen.findByRole("form", { name: "Change your password" });
    expect(form).toHaveTextContent("signs you out everywhere");
    fillPasswordForm(form, "oldpassword0", "newpassword1");
    fireEvent.click(within(form).getByRole("button", { name: "Change password" }));
    expect(await screen.findByText(/this one too: sign in again/)).toBeInTheDocument();
    const patch = fetch.mock.calls.find(([, i]) => i?.method === "PATCH")!;
    expect(patch[0]).toBe("/api/v1/users/alice");
    expect(JSON.parse(String(patch[1]?.body))).toEqual({ password: "newpassword1", current_password: "oldpassword0" });
  });

  it("says so when the current password is missing or wrong, and stays signed in", async () => {
    const fetch = mockFetch((url, init) => {
      if (url === "/api/v1/auth/me") return jsonResponse(alice);
      if (init?.method === "PATCH") {
        const body = JSON.parse(String(init.body)) as { current_password?: string };
        if (!body.current_password) return problem(422, "to change your own password, send the one you have now as current_password");
        return problem(403, "the current password is wrong; nothing was changed");
      }
      return jsonResponse({ tokens: [] });
    });
    renderPage();
    const form = await screen.findByRole("form", { name: "Change your password" });
    fillPasswordForm(form, "", "newpassword1");
    fireEvent.click(within(form).getByRole("button", { name: "Change password" }));
    expect(await within(form).findByRole("alert")).toHaveTextContent("Enter your current password");
    const first = fetch.mock.calls.find(([, i]) => i?.method === "PATCH")!;
    expect(JSON.parse(String(first[1]?.body))).toEqual({ password: "newpassword1" });

    fillPasswordForm(form, "not-the-one", "newpassword1");
    fireEvent.click(within(form).getByRole("button", { name: "Change password" }));
    await vi.waitFor(() => expect(within(form).getByRole("alert")).toHaveTextContent("the current password is wrong"));
    expect(screen.queryByText(/this one too: sign in again/)).not.toBeInTheDocument();
    expect(getToken()).toBe("tl_SessionToken");
  });

  it("marks this session's token and warns that revoking it signs you out", async () => {
    const confirm = vi.spyOn(window, "confirm").mockReturnValue(false);
    const fetch = mockFetch((url) => (url === "/api/v1/auth/me" ? jsonResponse(alice) : jsonResponse({ tokens: [session, ci] })));
    renderPage();
    const table = await screen.findByTestId("token-table");
    const current = (await within(table).findByText("login session")).closest("tr")!;
    expect(current).toHaveTextContent("this session");
    expect(within(table).getByText("ci").closest("tr")!).not.toHaveTextContent("this session");
    expect(within(table).queryByRole("columnheader", { name: "User" })).not.toBeInTheDocument();

    fireEvent.click(within(current).getByRole("button", { name: "Revoke and sign out" }));
    expect(confirm).toHaveBeenCalledWith(expect.stringContaining("you will be signed out"));
    fireEvent.click(within(within(table).getByText("ci").closest("tr")!).getByRole("button", { name: "Revoke" }));
    expect(confirm).toHaveBeenLastCalledWith(expect.not.stringContaining("signed out"));
    expect(fetch.mock.calls.some(([, i]) => i?.method === "DELETE")).toBe(false);
  });

  it("shows whose each token is in the admin's list of all tokens", async () => {
    const bobs: TokenInfo = { ...ci, id: 9, name: "ingest job", username: "bob" };
    const mine: TokenInfo = { ...session, username: "root" };
    mockFetch((url) => {
      if (url === "/api/v1/auth/me") return jsonResponse(root);
      if (url === "/api/v1/users") return jsonResponse({ users: [root] });
      if (url === "/api/v1/tokens?all=true") return jsonResponse({ tokens: [mine, bobs] });
      return jsonResponse({ tokens: [mine] });
    });
    renderPage();
    await screen.findByText("ingest job");
    const [own, all] = screen.getAllByTestId("token-table");
    expect(within(own!).queryByRole("columnheader", { name: "User" })).not.toBeInTheDocument();
    expect(within(all!).getByRole("columnheader", { name: "User" })).toBeInTheDocument();
    const bobRow = within(all!).getByText("ingest job").closest("tr")!;
    expect(within(bobRow).getAllByRole("cell")[0]).toHaveTextContent("bob");
    expect(within(all!).getByText("login session").closest("tr")!).toHaveTextContent("root");
  });
});
