import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen } from "@testing-library/react";
import { MemoryRouter } from "react-router-dom";
import { App } from "./App";
import { getToken, setToken } from "./api/client";
import { jsonResponse, mockFetch, problem } from "./test/fetch";

afterEach(() => vi.unstubAllGlobals());

function renderAt(path: string) {
  return render(
    <MemoryRouter initialEntries={[path]} future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <App />
    </MemoryRouter>,
  );
}

describe("App", () => {
  it("signs in, keeps the token in sessionStorage and shows the catalog", async () => {
    const fetch = mockFetch((url) => {
      if (url === "/api/v1/auth/login") return jsonResponse({ token: "tl_new", token_type: "bearer", expires: null });
      if (url === "/api/v1/auth/me") return jsonResponse({ username: "alice", is_admin: false, groups: [] });
      if (url.startsWith("/api/v1/twins")) return jsonResponse({ items: [], next_cursor: null });
      return problem(404, "no route");
    });
    renderAt("/");
    fireEvent.change(await screen.findByLabelText("Username"), { target: { value: "alice" } });
    fireEvent.change(screen.getByLabelText("Password"), { target: { value: "pw" } });
    fireEvent.click(screen.getByRole("button", { name: "Sign in" }));
    expect(await screen.findByText("alice")).toBeInTheDocument();
    expect(await screen.findByText(/no twins you may see/)).toBeInTheDocument();
    expect(getToken()).toBe("tl_new");
    expect(JSON.parse(String(fetch.mock.calls[0]![1]?.body))).toEqual({ username: "alice", password: "pw" });
  });

  it("shows a wrong password's detail on the login page", async () => {
    mockFetch(() => problem(401, "wrong username or password."));
    renderAt("/login");
    fireEvent.change(screen.getByLabelText("Username"), { target: { value: "a" } });
    fireEvent.change(screen.getByLabelText("Password"), { target: { value: "b" } });
    fireEvent.click(screen.getByRole("button", { name: "Sign in" }));
    expect(await screen.findByRole("alert")).toHaveTextContent("wrong username or password.");
  });

  it("returns to the login with a message when the token is refused", async () => {
    setToken("tl_expired");
    mockFetch(() => problem(401, "the token has expired."));
    renderAt("/twins/tingen");
    expect(await screen.findByRole("button", { name: "Sign in" })).toBeInTheDocument();
    expect(screen.getByText(/session has ended.*the token has expired/)).toBeInTheDocument();
    expect(getToken()).toBeNull();
  });

  it("shows a twin API error as a readable message", async () => {
    setToken("tl_ok");
    mockFetch((url) =>
      url === "/api/v1/auth/me" ? jsonResponse({ username: "bob", is_admin: false, groups: [] }) : problem(404, "no twin 'nope'"),
    );
    renderAt("/twins/nope");
    expect(await screen.findByRole("alert")).toHaveTextContent("no twin 'nope'");
  });
});
