import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import { MemoryRouter } from "react-router-dom";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { RelationTree } from "./RelationTree";
import { TREE_CONCURRENCY } from "./useRelationForest";

afterEach(() => vi.unstubAllGlobals());

const summary = (slug: string, name: string) => ({
  slug,
  id: `urn:${slug}`,
  name,
  url: `http://127.0.0.1:8000/twins/${slug}`,
  created: "2026-11-21T10:00:00Z",
  modified: "2026-11-21T10:00:00Z",
  levels: ["public"],
});
const TWINS = [summary("crane", "Ilmatar crane"), summary("hall", "Hall"), summary("tingen", "Tingen")];
const SUBTREES: Record<string, unknown> = {
  hall: {
    id: "urn:hall",
    slug: "hall",
    name: "Hall",
    nodes: [{ id: "urn:crane", slug: "crane", name: "Ilmatar crane", nodes: [] }],
  },
  crane: { id: "urn:crane", slug: "crane", name: "Ilmatar crane", nodes: [] },
  tingen: { id: "urn:tingen", slug: "tingen", name: "Tingen", nodes: [] },
};

function renderTree() {
  return render(
    <MemoryRouter future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <RelationTree />
    </MemoryRouter>,
  );
}

/** The fake server: the twin list, and each twin's subtree (or `failing` for some). */
function serve(failing: (slug: string) => boolean = () => false) {
  let inFlight = 0;
  const stats = { most: 0 };
  const fetch = mockFetch(async (url) => {
    if (url.startsWith("/api/v1/twins?")) return jsonResponse({ items: TWINS, next_cursor: null });
    const slug = /\/api\/v1\/twins\/([^/]+)\/relations/.exec(url)?.[1] ?? "";
    inFlight += 1;
    stats.most = Math.max(stats.most, inFlight);
    await new Promise((resolve) => setTimeout(resolve, 1));
    inFlight -= 1;
    return failing(slug) ? problem(500, "database is locked") : jsonResponse(SUBTREES[slug]);
  });
  return { fetch, stats };
}

describe("RelationTree", () => {
  it("builds the tree from each twin's relations, a few requests at a time", async () => {
    const { fetch, stats } = serve();
    renderTree();
    const tree = await screen.findByRole("list", { name: "Relation tree" });
    expect(fetch.mock.calls.map((c) => c[0])).toContain("/api/v1/twins/hall/relations?direction=down&depth=3");
    expect(stats.most).toBeLessThanOrEqual(TREE_CONCURRENCY);

    // the hall and Tingen are roots; the crane is the hall's child
    const roots = within(tree).getAllByRole("listitem").filter((li) => li.parentElement === tree);
    expect(roots.map((li) => within(li).getAllByRole("link")[0]!.textContent)).toEqual(["Hall", "Tingen"]);
    const crane = within(roots[0]!).getByRole("link", { name: "Ilmatar crane" });
    expect(crane).toHaveAttribute("href", "/twins/crane");
    expect(crane.parentElement).toHaveTextContent("child");
    expect(within(roots[1]!).getByText("top level")).toBeInTheDocument();

    // a node with children collapses and expands
    const toggle = within(roots[0]!).getByRole("button", { name: "Collapse Hall" });
    expect(toggle).toHaveAttribute("aria-expanded", "true");
    fireEvent.click(toggle);
    expect(within(roots[0]!).queryByRole("link", { name: "Ilmatar crane" })).not.toBeInTheDocument();
    expect(within(roots[0]!).getByText("1 below")).toBeInTheDocument();
    fireEvent.click(within(roots[0]!).getByRole("button", { name: "Expand Hall" }));
    expect(within(roots[0]!).getByRole("link", { name: "Ilmatar crane" })).toBeInTheDocument();
  });

  it("says so when there are no twins", async () => {
    mockFetch(() => jsonResponse({ items: [], next_cursor: null }));
    renderTree();
    expect(await screen.findByText(/no twins you may see/)).toBeInTheDocument();
  });

  it("shows what it has when some relations fail, and an error with a retry when all do", async () => {
    serve((slug) => slug === "tingen");
    const { unmount } = renderTree();
    expect(await screen.findByRole("list", { name: "Relation tree" })).toBeInTheDocument();
    expect(screen.getByText(/relations of 1 twin could not be loaded \(database is locked\)/)).toBeInTheDocument();
    unmount();

    serve(() => true);
    renderTree();
    expect(await screen.findByRole("alert")).toHaveTextContent("database is locked");
    expect(screen.getByRole("button", { name: "Retry" })).toBeInTheDocument();
  });

  it("shows the error when the twins cannot be listed", async () => {
    mockFetch(() => problem(503, "the store is starting"));
    renderTree();
    expect(await screen.findByRole("alert")).toHaveTextContent("the store is starting");
  });
});
