import { describe, expect, it } from "vitest";
import { render, screen } from "@testing-library/react";
import { MemoryRouter } from "react-router-dom";
import type { RelationNode } from "../../api/types";
import { RelationLinks } from "./Relations";

function renderLinks(root: RelationNode) {
  return render(
    <MemoryRouter future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <RelationLinks title="Parents" root={root} />
    </MemoryRouter>,
  );
}

describe("RelationLinks", () => {
  it("links a twin of another instance to its document, with its name and state", () => {
    renderLinks({
      id: "urn:pump",
      slug: "pump",
      name: "Pump",
      nodes: [
        {
          id: "https://other.example.org/twins/plant",
          registered: false,
          remote: {
            url: "https://other.example.org/twins/plant",
            name: "Plant",
            state: "stale",
            fetched_at: "2026-11-26T10:00:00Z",
            remote_id: 3,
          },
          nodes: [],
        },
        { id: "urn:local", slug: "local", name: "Local parent", nodes: [] },
        { id: "urn:elsewhere", registered: false, nodes: [] },
      ],
    });
    const remote = screen.getByRole("link", { name: "Plant" });
    expect(remote.getAttribute("href")).toBe("https://other.example.org/twins/plant");
    expect(remote.getAttribute("rel")).toBe("noopener noreferrer");
    expect(screen.getByText("remote")).toBeTruthy();
    expect(screen.getByText("stale").getAttribute("title")).toMatch(/out of date/);
    expect(screen.getByText(/fetched 2026-11-26T10:00:00Z/)).toBeTruthy();
    expect(screen.getByRole("link", { name: "Local parent" }).getAttribute("href")).toBe("/twins/local");
    expect(screen.getByText("urn:elsewhere")).toBeTruthy();
  });

  it("shows the id of a remote twin not fetched yet", () => {
    renderLinks({
      id: "urn:pump",
      nodes: [
        {
          id: "https://slow.example.org/twins/x",
          registered: false,
          remote: { url: "https://slow.example.org/twins/x", name: "", state: "pending", fetched_at: null },
          nodes: [],
        },
      ],
    });
    expect(screen.getByRole("link", { name: "https://slow.example.org/twins/x" })).toBeTruthy();
    expect(screen.getByText("pending")).toBeTruthy();
  });
});
