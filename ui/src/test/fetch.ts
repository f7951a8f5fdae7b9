import { vi } from "vitest";

export function jsonResponse(body: unknown, status = 200, contentType = "application/json"): Response {
  return new Response(JSON.stringify(body), { status, headers: { "Content-Type": contentType } });
}

export function problem(status: number, detail: string): Response {
  return jsonResponse({ type: "about:blank", title: "Error", status, detail }, status, "application/problem+json");
}

/** Replace global fetch with a mock; returns it for assertions. */
export function mockFetch(impl: (url: string, init?: RequestInit) => Response | Promise<Response>) {
  const fn = vi.fn((input: RequestInfo | URL, init?: RequestInit) => Promise.resolve(impl(String(input), init)));
  vi.stubGlobal("fetch", fn);
  return fn;
}
