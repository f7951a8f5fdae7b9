import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen } from "@testing-library/react";
import { MemoryRouter, Route, Routes, useLocation } from "react-router-dom";
import { jsonResponse, mockFetch } from "../test/fetch";
import { CatalogPage } from "./CatalogPage";

afterEach(() => vi.unstubAllGlobals());

const HALL = {
  slug: "hall",
  id: "urn:hall",
  name: "Hall",
  url: "http://127.0.0.1:8000/twins/hall",
  created: "2026-11-21T10:00:00Z",
  modified: "2026-11-21T10:00:00Z",
  levels: ["public"],
};

function serve() {
  return mockFetch((url) => {
    if (url.startsWith("/api/v1/search")) {
      const facets = { keywords: [{ value: "PLC", count: 1 }], counted_hits: 1 };
      return jsonResponse({ query: "", keyword: null, total: 1, limit: 1, offset: 0, hits: [], facets });
    }
    if (url.startsWith("/api/v1/twins/hall/relations")) return jsonResponse({ ...HALL, nodes: [] });
    return jsonResponse({ items: [HALL], next_cursor: null });
  });
}

function Where() {
  const location = useLocation();
  return <output aria-label="location">{location.pathname + location.search}</output>;
}

function renderCatalog(at = "/") {
  return render(
    <MemoryRouter initialEntries={[at]} future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <Routes>
        <Route
          index
          element={
            <>
              <CatalogPage />
              <Where />
            </>
          }
        />
      </Routes>
    </MemoryRouter>,
  );
}

describe("CatalogPage", () => {
  it("switches between the list and the relation tree, keeping the view in the URL", async () => {
    serve();
    renderCatalog();
    expect(await screen.findByRole("table")).toBeInTheDocument();
    expect(screen.getByRole("button", { name: "List" })).toHaveAttribute("aria-pressed", "true");
    // the catalog's keywords show before anything is typed
    expect(await screen.findByRole("button", { name: /PLC/ })).toBeInTheDocument();

    fireEvent.click(screen.getByRole("button", { name: "Tree" }));
    expect(screen.getByLabelText("location")).toHaveTextContent("/?view=tree");
    expect(await screen.findByRole("list", { name: "Relation tree" })).toBeInTheDocument();
    expect(screen.getByRole("link", { name: "Hall" })).toHaveAttribute("href", "/twins/hall");
    expect(screen.getByText(/flat/)).toBeInTheDocument();

    fireEvent.click(screen.getByRole("button", { name: "List" }));
    expect(screen.getByLabelText("location")).toHaveTextContent(/^\/$/);
    expect(await screen.findByRole("table")).toBeInTheDocument();
  });

  it("opens on the tree when the URL asks for it", async () => {
    serve();
    renderCatalog("/?view=tree");
    expect(await screen.findByRole("list", { name: "Relation tree" })).toBeInTheDocument();
    expect(screen.getByRole("button", { name: "Tree" })).toHaveAttribute("aria-pressed", "true");
  });
});
