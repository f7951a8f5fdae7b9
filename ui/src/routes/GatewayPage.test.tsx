import { afterEach, describe, expect, it, vi } from "vitest";
import { render, screen, within } from "@testing-library/react";
import { MemoryRouter } from "react-router-dom";
import { AuthProvider } from "../auth/AuthContext";
import { setToken } from "../api/client";
import { GatewayPage } from "./GatewayPage";
import { statusClasses } from "../components/gateway/ServicesTable";
import { jsonResponse, mockFetch, problem } from "../test/fetch";

afterEach(() => vi.unstubAllGlobals());

const service = (name: string, twin: string) => ({
  name,
  twin,
  source: "document",
  base_url: `http://127.0.0.1:9/${name}`,
  feature: null,
  description: null,
  auth: { method: "bearer" },
  methods: ["GET"],
  health_path: null,
  blocked: null,
  gateway_path: `/twins/${twin}/services/${name}/`,
  health: null,
  requests: 5,
  stats: {
    statuses: { "200": 3, "204": 1, "502": 1 },
    failures: { upstream_connect: 1 },
    bytes_in: 0,
    bytes_out: 10,
    upstream_ms: { mean: 1.25, p50: 1, p95: 2.5 },
  },
  credential_refreshes: 0,
  credential_error: null,
});

const entry = (twin: string) => ({
  id: 1, time: 0, time_iso: "2026-11-22T06:00:00Z", twin, service: "historian", caller: "bob",
  method: "GET", path: "/signals", status: 200, outcome: "forwarded", bytes_in: 0, bytes_out: 10,
  upstream_ms: 1.2, total_ms: 1.5,
});

function renderAs(isAdmin: boolean) {
  setToken("tl_x");
  const fetch = mockFetch((url) => {
    if (url === "/api/v1/auth/me") return jsonResponse({ username: "bob", is_admin: isAdmin, groups: [] });
    if (url.startsWith("/api/v1/twins?")) {
      return jsonResponse({ items: [{ slug: "mine", name: "My crane" }, { slug: "theirs", name: "Their crane" }], next_cursor: null });
    }
    const services = url.match(/^\/api\/v1\/twins\/(\w+)\/services$/);
    if (services) return jsonResponse({ services: [service("historian", services[1]!)] });
    if (url.startsWith("/api/v1/gateway/audit")) {
      if (url.includes("twin=theirs") || (!isAdmin && !url.includes("twin="))) return problem(403, "owners only");
      return jsonResponse({ entries: [entry(url.includes("twin=mine") ? "mine" : "any")] });
    }
    return problem(404, "no route");
  });
  render(
    <MemoryRouter future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <AuthProvider>
        <GatewayPage />
      </AuthProvider>
    </MemoryRouter>,
  );
  return fetch;
}

describe("GatewayPage", () => {
  it("shows each service's answers by status class and its service time", async () => {
    renderAs(true);
    expect(await screen.findAllByText("2xx 4")).toHaveLength(2); // one table per twin
    expect(screen.getAllByText("5xx 1")).toHaveLength(2);
    expect(screen.getAllByText("1.3 ms (p95 ≤ 2.5 ms)")).toHaveLength(2);
  });

  it("shows an owner the log of the twins they own only", async () => {
    const fetch = renderAs(false);
    expect(await screen.findByRole("heading", { name: "My crane", level: 3 })).toBeInTheDocument();
    expect(await screen.findByText("bob")).toBeInTheDocument();
    const audits = fetch.mock.calls.map(([url]) => String(url)).filter((u) => u.includes("/gateway/audit"));
    expect(audits.some((u) => u.includes("twin=mine&") || u.endsWith("twin=mine"))).toBe(true);
    expect(audits.every((u) => u.includes("twin="))).toBe(true);
    const log = screen.getByRole("region", { name: "Recent requests" });
    expect(within(log).queryByText("Their crane")).toBeNull();
    expect(within(log).getByText("My crane")).toBeInTheDocument();
  });

  it("groups statuses into classes", () => {
    expect(statusClasses({ statuses: { "200": 2, "201": 1, "404": 4 }, failures: {}, bytes_in: 0, bytes_out: 0, upstream_ms: null })).toEqual([
      ["2xx", 3],
      ["4xx", 4],
    ]);
  });
});
