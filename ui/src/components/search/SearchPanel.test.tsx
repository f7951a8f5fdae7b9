import { afterEach, describe, expect, it, vi } from "vitest";
import { act, fireEvent, render, screen, within } from "@testing-library/react";
import { MemoryRouter } from "react-router-dom";
import { SearchPanel, SEARCH_DEBOUNCE_MS } from "./SearchPanel";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { splitSnippet } from "./Snippet";

const ANSWER = {
  query: "crane",
  keyword: null,
  total: 1,
  limit: 50,
  offset: 0,
  hits: [
    {
      slug: "ilmatar-k16052",
      name: "Ilmatar crane",
      score: 6.3,
      matches: [
        { feature: null, privacy: "public", snippet: "Ilmatar <mark>crane</mark>" },
        { feature: "OPC UA server", privacy: "group-1", snippet: "the <mark>crane</mark>&#x27;s local &lt;b&gt;" },
      ],
    },
  ],
  facets: { keywords: [{ value: "CAD", count: 1 }], counted_hits: 1 },
};

/** The catalog's keywords: what the server answers to an empty query. */
const CATALOG = {
  query: "",
  keyword: null,
  total: 3,
  limit: 1,
  offset: 0,
  hits: [{ slug: "hall", name: "Hall", score: 0, matches: [] }],
  facets: { keywords: [{ value: "PLC", count: 2 }, { value: "CAD", count: 1 }], counted_hits: 3 },
};

const CATALOG_URL = "/api/v1/search?limit=1";
const searchCalls = (fetch: ReturnType<typeof mockFetch>) =>
  fetch.mock.calls.map((call) => String(call[0])).filter((url) => url !== CATALOG_URL);

afterEach(() => {
  vi.useRealTimers();
  vi.unstubAllGlobals();
});

function renderPanel() {
  return render(
    <MemoryRouter future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <SearchPanel>
        <p>the catalog</p>
      </SearchPanel>
    </MemoryRouter>,
  );
}

async function flush() {
  await act(async () => {
    await Promise.resolve();
  });
}

describe("SearchPanel", () => {
  it("waits until typing stops, then searches once and shows ranked hits with the matching feature", async () => {
    vi.useFakeTimers();
    const fetch = mockFetch((url) => jsonResponse(url === CATALOG_URL ? CATALOG : ANSWER));
    renderPanel();
    expect(screen.getByText("the catalog")).toBeInTheDocument();
    const box = screen.getByLabelText("Search twins and features");
    fireEvent.change(box, { target: { value: "c" } });
    act(() => vi.advanceTimersByTime(100));
    fireEvent.change(box, { target: { value: "cra" } });
    act(() => vi.advanceTimersByTime(100));
    fireEvent.change(box, { target: { value: "crane" } });
    act(() => vi.advanceTimersByTime(SEARCH_DEBOUNCE_MS - 1));
    expect(searchCalls(fetch)).toEqual([]);
    act(() => vi.advanceTimersByTime(1));
    await flush();
    await flush();
    expect(searchCalls(fetch)).toEqual(["/api/v1/search?q=crane&limit=50"]);

    expect(screen.getByRole("link", { name: "Ilmatar crane" })).toHaveAttribute("href", "/twins/ilmatar-k16052");
    // the feature that matched links to its card on the twin's page
    expect(screen.getByRole("link", { name: "OPC UA server" })).toHaveAttribute(
      "href",
      "/twins/ilmatar-k16052#feature-opc-ua-server",
    );
    // the snippet is decoded text with the match marked, never inserted as HTML
    expect(screen.getByText("'s local <b>")).toBeInTheDocument();
    expect(document.querySelectorAll("mark")).toHaveLength(2);
    expect(screen.queryByText("the catalog")).not.toBeInTheDocument();

    // a keyword facet filters the search
    fireEvent.click(screen.getByRole("button", { name: /CAD/ }));
    await flush();
    await flush();
    expect(searchCalls(fetch)[1]).toBe("/api/v1/search?q=crane&keyword=CAD&limit=50");
  });

  it("shows the catalog's keywords before anything is typed, and filters by one on a click", async () => {
    const fetch = mockFetch((url) => jsonResponse(url === CATALOG_URL ? CATALOG : { ...ANSWER, query: "", keyword: "PLC" }));
    renderPanel();
    const facets = await screen.findByRole("complementary", { name: "Keywords" });
    expect(screen.getByText("the catalog")).toBeInTheDocument();
    expect(fetch.mock.calls.map((call) => call[0])).toEqual([CATALOG_URL]);

    fireEvent.click(within(facets).getByRole("button", { name: /PLC/ }));
    expect(await screen.findByRole("link", { name: "Ilmatar crane" })).toBeInTheDocument();
    expect(searchCalls(fetch)).toEqual(["/api/v1/search?keyword=PLC&limit=50"]);
    expect(screen.queryByText("the catalog")).not.toBeInTheDocument();

    // the chip in the search bar removes the filter: the catalog is back
    fireEvent.click(screen.getByTitle("Remove this filter"));
    expect(await screen.findByText("the catalog")).toBeInTheDocument();
  });

  it("keeps the catalog when its keywords cannot be loaded", async () => {
    mockFetch(() => problem(500, "database is locked"));
    renderPanel();
    await flush();
    await flush();
    expect(screen.getByText("the catalog")).toBeInTheDocument();
    expect(screen.queryByRole("complementary", { name: "Keywords" })).not.toBeInTheDocument();
    expect(screen.queryByRole("alert")).not.toBeInTheDocument();
  });

  it("shows the problem detail when the search fails", async () => {
    mockFetch(() => problem(422, "q: at most 256 characters"));
    renderPanel();
    fireEvent.change(screen.getByLabelText("Search twins and features"), { target: { value: "x" } });
    expect(await screen.findByRole("alert")).toHaveTextContent("q: at most 256 characters");
  });

  it("says so when nothing matches", async () => {
    mockFetch(() => jsonResponse({ ...ANSWER, query: "zzz", total: 0, hits: [], facets: { keywords: [] } }));
    renderPanel();
    fireEvent.change(screen.getByLabelText("Search twins and features"), { target: { value: "zzz" } });
    expect(await screen.findByText(/No twin or library asset matches/)).toBeInTheDocument();
  });
});

describe("library assets among the hits", () => {
  it("lists an asset after the twins, linked to its place in the library", async () => {
    const asset = {
      kind: "asset", slug: null, name: "tingen-beam", score: 0, matches: [], ref: "common/models/tingen-beam",
      scope: "common", asset_kind: "models", description: "the beam's first mode",
    };
    mockFetch(() => jsonResponse({ ...ANSWER, total: 2, hits: [{ kind: "twin", ...ANSWER.hits[0] }, asset] }));
    renderPanel();
    fireEvent.change(screen.getByLabelText("Search twins and features"), { target: { value: "crane" } });
    const link = await screen.findByRole("link", { name: "tingen-beam" });
    expect(link).toHaveAttribute("href", "/library?asset=common%2Fmodels%2Ftingen-beam");
    const hits = link.closest("ol")!.querySelectorAll(":scope > li");
    expect([...hits].map((li) => li.querySelector(".hit-title a")?.textContent)).toEqual(["Ilmatar crane", "tingen-beam"]);
    expect(link.closest("li")).toHaveTextContent("common/models/tingen-beammodelsthe beam's first mode");
    expect(screen.getByText("2 matches.")).toBeInTheDocument();
  });
});

describe("splitSnippet", () => {
  it("splits marks and decodes entities", () => {
    expect(splitSnippet("a <mark>b&amp;c</mark> d")).toEqual([
      { text: "a ", marked: false },
      { text: "b&c", marked: true },
      { text: " d", marked: false },
    ]);
  });
});
