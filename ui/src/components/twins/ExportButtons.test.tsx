import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen } from "@testing-library/react";
import { ExportButtons } from "./ExportButtons";
import { setToken } from "../../api/client";
import { mockFetch, problem } from "../../test/fetch";

// jsdom has no object URLs.
const urlStatics = URL as unknown as Record<string, unknown>;
let click: ReturnType<typeof vi.spyOn>;
beforeEach(() => {
  setToken("tl_secret");
  urlStatics.createObjectURL = vi.fn(() => "blob:x");
  urlStatics.revokeObjectURL = vi.fn();
  click = vi.spyOn(HTMLAnchorElement.prototype, "click").mockImplementation(() => {});
});
afterEach(() => {
  vi.unstubAllGlobals();
  click.mockRestore();
  delete urlStatics.createObjectURL;
  delete urlStatics.revokeObjectURL;
});

const savedAs = () => (click.mock.contexts.at(-1) as HTMLAnchorElement).download;

describe("ExportButtons", () => {
  it("fetches each format from the server with the token and saves it", async () => {
    const fetch = mockFetch((url) =>
      url.endsWith("/export.aasx")
        ? new Response("PK", { headers: { "Content-Disposition": 'attachment; filename="tingen.aasx"' } })
        : new Response("{}"),
    );
    render(<ExportButtons slug="tingen" />);
    const expected: [string, string, string, string][] = [
      ["YAML", "/twins/tingen?format=yaml", "application/yaml", "tingen.yaml"],
      ["JSON", "/twins/tingen?format=json", "application/json", "tingen.json"],
      ["WoT TD", "/twins/tingen?format=wot-td", "application/td+json", "tingen.td.json"],
      ["DTDL", "/twins/tingen?format=dtdl", "application/ld+json", "tingen.dtdl.json"],
      ["AAS JSON", "/twins/tingen?format=aas-json", "application/json", "tingen.aas.json"],
      ["AASX", "/twins/tingen/export.aasx", "application/asset-administration-shell-package+xml", "tingen.aasx"],
    ];
    for (const [label, url, accept, file] of expected) {
      fireEvent.click(screen.getByRole("button", { name: label }));
      expect(await screen.findByText(`Saved ${file}`)).toBeInTheDocument();
      const [called, init] = fetch.mock.calls.at(-1)!;
      expect(called).toBe(url);
      expect(init?.headers).toMatchObject({ Accept: accept, Authorization: "Bearer tl_secret" });
      expect(savedAs()).toBe(file);
    }
    expect(click).toHaveBeenCalledTimes(expected.length);
  });

  it("quotes the slug in the path", async () => {
    const fetch = mockFetch(() => new Response("{}"));
    render(<ExportButtons slug="a b" />);
    fireEvent.click(screen.getByRole("button", { name: "DTDL" }));
    expect(await screen.findByText("Saved a b.dtdl.json")).toBeInTheDocument();
    expect(fetch.mock.calls[0]![0]).toBe("/twins/a%20b?format=dtdl");
  });

  it("shows the server's refusal and saves nothing", async () => {
    mockFetch(() => problem(404, "No twin 'tingen' (or you may not see it)."));
    render(<ExportButtons slug="tingen" />);
    fireEvent.click(screen.getByRole("button", { name: "WoT TD" }));
    expect(await screen.findByRole("alert")).toHaveTextContent("Error (404): No twin 'tingen'");
    expect(click).not.toHaveBeenCalled();
    expect(screen.getByRole("button", { name: "WoT TD" })).toBeEnabled();
  });
});
