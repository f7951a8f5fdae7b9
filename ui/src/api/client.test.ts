import { afterEach, describe, expect, it, vi } from "vitest";
import { ApiError, apiFetch, getToken, onUnauthorized, setToken } from "./client";
import { jsonResponse, mockFetch, problem } from "../test/fetch";

afterEach(() => vi.unstubAllGlobals());

describe("apiFetch", () => {
  it("sends the token as a bearer token and returns the JSON", async () => {
    setToken("tl_secret");
    const fetch = mockFetch(() => jsonResponse({ items: [], next_cursor: null }));
    const answer = await apiFetch("/api/v1/twins", { query: { limit: 5, cursor: null } });
    expect(answer).toEqual({ items: [], next_cursor: null });
    const [url, init] = fetch.mock.calls[0]!;
    expect(url).toBe("/api/v1/twins?limit=5");
    expect((init?.headers as Record<string, string>).Authorization).toBe("Bearer tl_secret");
  });

  it("throws an ApiError with the problem's detail", async () => {
    mockFetch(() => problem(404, "no twin 'crane'"));
    const error = await apiFetch("/api/v1/twins/crane").catch((e: unknown) => e);
    expect(error).toBeInstanceOf(ApiError);
    expect((error as ApiError).status).toBe(404);
    expect((error as ApiError).message).toBe("no twin 'crane'");
  });

  it("falls back to the status when the answer is not a problem document", async () => {
    mockFetch(() => new Response("<html>bad gateway</html>", { status: 502, statusText: "Bad Gateway" }));
    await expect(apiFetch("/x")).rejects.toThrow("502 Bad Gateway");
  });

  it("on 401 forgets the token and tells the listeners", async () => {
    setToken("tl_old");
    const listener = vi.fn();
    const stop = onUnauthorized(listener);
    mockFetch(() => problem(401, "the token has expired."));
    await expect(apiFetch("/api/v1/auth/me")).rejects.toBeInstanceOf(ApiError);
    expect(getToken()).toBeNull();
    expect(listener).toHaveBeenCalledWith("the token has expired.");
    stop();
  });

  it("a 401 at login is a wrong password, not a lost session", async () => {
    setToken("tl_keep");
    const listener = vi.fn();
    const stop = onUnauthorized(listener);
    const fetch = mockFetch(() => problem(401, "wrong username or password."));
    await expect(apiFetch("/api/v1/auth/login", { method: "POST", json: {}, anonymous: true })).rejects.toThrow(
      "wrong username or password.",
    );
    expect(listener).not.toHaveBeenCalled();
    expect((fetch.mock.calls[0]![1]?.headers as Record<string, string>).Authorization).toBeUndefined();
    expect(getToken()).toBe("tl_keep");
    stop();
  });

  it("reports an unreachable server readably", async () => {
    vi.stubGlobal("fetch", vi.fn(() => Promise.reject(new TypeError("Failed to fetch"))));
    await expect(apiFetch("/api/v1/twins")).rejects.toThrow(/cannot be reached/);
  });
});
