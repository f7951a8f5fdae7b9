import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, screen, waitFor } from "@testing-library/react";
import { DocumentTab } from "./DocumentTab";
import { jsonResponse, mockFetch } from "../../test/fetch";
import { renderTab, twinFixture } from "../../test/twin";

afterEach(() => vi.unstubAllGlobals());

const YAML = 'version: "1.0"\nprivacy: public\nname: Tingen\nfeatures: []\n';

function server(onPut: (url: string, body: string) => Response) {
  return mockFetch((url, init) => {
    if (url === "/api/v1/twins/tingen/parts") return jsonResponse({ levels: ["public"] });
    if (url === "/api/v1/twins/tingen/parts/public?format=yaml") {
      return new Response(YAML, { headers: { "Content-Type": "application/yaml" } });
    }
    if (init?.method === "PUT") return onPut(url, String(init.body));
    return jsonResponse({}, 404);
  });
}

const refused = () =>
  jsonResponse(
    {
      status: 422,
      title: "Unprocessable content",
      detail: "The DT document has problems; nothing was stored.",
      errors: [{ message: "must be 'parent', 'child' or 'sibling'", path: "relations[0].relationType", line: 5, column: 5, document: 0 }],
    },
    422,
    "application/problem+json",
  );

describe("DocumentTab", () => {
  it("checks an edit with a dry run and marks the problem at its line", async () => {
    const fetch = server(refused);
    renderTab(<DocumentTab />, twinFixture("editor"));
    const editor = await screen.findByLabelText("YAML of the public part");
    await waitFor(() => expect(editor).toHaveValue(YAML));
    const broken = `${YAML}relations:\n  - relationType: cousin\n`;
    fireEvent.change(editor, { target: { value: broken } });
    const problem = await screen.findByText(/Line 5, column 5: relations\[0\]\.relationType/, {}, { timeout: 3000 });
    expect(problem).toBeInTheDocument();
    const marked = document.querySelectorAll("[data-error-line]");
    expect([...marked].map((el) => el.getAttribute("data-error-line"))).toEqual(["5"]);
    const put = fetch.mock.calls.find(([, init]) => init?.method === "PUT")!;
    expect(put[0]).toBe("/api/v1/twins/tingen?dry_run=true");
    expect(put[1]?.body).toBe(broken);
    expect(screen.getByRole("button", { name: "Save" })).toBeDisabled();
  });

  it("saves a valid edit without a dry run and reloads the twin", async () => {
    const puts: string[] = [];
    server((url) => {
      puts.push(url);
      return jsonResponse({ slug: "tingen", outcome: "updated", levels: ["public"], ...(url.includes("dry_run") ? { dry_run: true } : {}) });
    });
    const reload = vi.fn();
    renderTab(<DocumentTab />, twinFixture("owner"), reload);
    const editor = await screen.findByLabelText("YAML of the public part");
    await waitFor(() => expect(editor).toHaveValue(YAML));
    fireEvent.change(editor, { target: { value: YAML.replace("Tingen", "Tingen rig") } });
    expect(await screen.findByText("Valid: ready to save", {}, { timeout: 3000 })).toBeInTheDocument();
    fireEvent.click(screen.getByRole("button", { name: "Save" }));
    await waitFor(() => expect(reload).toHaveBeenCalled());
    expect(puts).toEqual(["/api/v1/twins/tingen?dry_run=true", "/api/v1/twins/tingen"]);
  });

  it("is read only for a viewer", async () => {
    const fetch = server(refused);
    renderTab(<DocumentTab />, twinFixture("viewer"));
    const editor = await screen.findByLabelText("YAML of the public part");
    expect(editor).toHaveAttribute("readonly");
    expect(screen.queryByRole("button", { name: "Save" })).toBeNull();
    expect(screen.getByText(/needs the editor role/)).toBeInTheDocument();
    expect(fetch.mock.calls.some(([, init]) => init?.method === "PUT")).toBe(false);
  });
});
