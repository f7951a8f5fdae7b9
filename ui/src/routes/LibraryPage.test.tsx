import { afterEach, describe, expect, it, vi } from "vitest";
import { render, screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { MemoryRouter } from "react-router-dom";
import { AuthProvider } from "../auth/AuthContext";
import { setToken } from "../api/client";
import { jsonResponse, mockFetch, problem } from "../test/fetch";
import { LibraryPage, scopesOf } from "./LibraryPage";
import { nameFromFile, parseTags } from "../components/library/UploadForm";
import { archiveName, formatOf } from "../api/library";

afterEach(() => vi.unstubAllGlobals());

const d1 = `sha256:${"1".repeat(64)}`;
const d2 = `sha256:${"2".repeat(64)}`;
const asset = (kind: string, name: string, scope = "common") => ({
  scope, kind, name, ref: `${scope}/${kind}/${name}`, description: `the ${name}`, keywords: ["beam"], licence: "MIT", author: "NTNU",
  tags: { latest: d2, "1.0.0": d1 }, latest: d2, versions: 2, updated_ns: 1.7e18,
});
const version = (digest: string, tags: string[]) => ({ digest, size: 2048, tags, meta: {}, created_ns: 1.7e18, created_by: "admin" });

function setup(extra: (url: string, init?: RequestInit) => Response | null = () => null) {
  setToken("tl_x");
  const fetch = mockFetch((url, init) => {
    const answer = extra(url, init);
    if (answer) return answer;
    if (url === "/api/v1/auth/me") return jsonResponse({ username: "ann", is_admin: false, groups: ["ntnu"] });
    if (url.startsWith("/api/v1/library?")) {
      const kind = new URLSearchParams(url.split("?")[1]).get("kind");
      const all = [asset("models", "tingen-beam"), asset("twins", "tingen-rig")];
      return jsonResponse({ assets: all.filter((a) => !kind || a.kind === kind) });
    }
    if (url === "/api/v1/library/common/models/tingen-beam") return jsonResponse({ ...asset("models", "tingen-beam"), versions: [version(d2, ["latest"]), version(d1, ["1.0.0"])] });
    if (url === `/api/v1/library/common/models/tingen-beam/versions/${encodeURIComponent(d1)}` && init?.method === "DELETE") {
      return problem(409, "version sha256:1111 of common/models/tingen-beam is held by deployment:rig-a");
    }
    return problem(404, `unexpected ${url}`);
  });
  render(
    <MemoryRouter future={{ v7_startTransition: true, v7_relativeSplatPath: true }}>
      <AuthProvider>
        <LibraryPage />
      </AuthProvider>
    </MemoryRouter>,
  );
  return fetch;
}

const urls = (fetch: ReturnType<typeof mockFetch>) => fetch.mock.calls.map(([u]) => String(u));

describe("LibraryPage", () => {
  it("lists the assets with their tags, and narrows them by kind", async () => {
    const fetch = setup();
    const table = await screen.findByRole("table", { name: "Assets" });
    expect(within(table).getByRole("button", { name: "common/models/tingen-beam" })).toBeInTheDocument();
    expect(within(table).getByRole("button", { name: "common/twins/tingen-rig" })).toBeInTheDocument();
    await userEvent.click(screen.getByRole("button", { name: "twins" }));
    await vi.waitFor(() => expect(within(screen.getByRole("table", { name: "Assets" })).queryByText("common/models/tingen-beam")).toBeNull());
    expect(urls(fetch)).toContain("/api/v1/library?kind=twins&limit=200");
  });

  it("searches with the asset list's q", async () => {
    const fetch = setup();
    await screen.findByRole("table", { name: "Assets" });
    await userEvent.type(screen.getByLabelText("Search the library"), "beam");
    await vi.waitFor(() => expect(urls(fetch)).toContain("/api/v1/library?q=beam&limit=200"));
  });

  it("opens an asset's versions and shows why a held version cannot be deleted", async () => {
    setup();
    vi.spyOn(window, "confirm").mockReturnValue(true);
    await userEvent.click(await screen.findByRole("button", { name: "common/models/tingen-beam" }));
    const versions = await screen.findByRole("table", { name: "Versions" });
    expect(within(versions).getAllByRole("row")).toHaveLength(3);
    expect(within(versions).getByText("1.0.0")).toBeInTheDocument();
    await userEvent.click(within(versions).getByRole("button", { name: `Delete ${d1.slice(0, 19)}` }));
    expect(await screen.findByRole("alert")).toHaveTextContent("(409): version sha256:1111 of common/models/tingen-beam is held by deployment:rig-a");
  });

  it("deletes a whole asset after asking, and closes it", async () => {
    const deleted: string[] = [];
    setup((url, init) => {
      if (init?.method !== "DELETE") return null;
      deleted.push(url);
      return new Response(null, { status: 204 });
    });
    const confirm = vi.spyOn(window, "confirm").mockReturnValue(true);
    await userEvent.click(await screen.findByRole("button", { name: "common/models/tingen-beam" }));
    await userEvent.click(await screen.findByRole("button", { name: "Delete asset" }));
    expect(confirm).toHaveBeenCalledWith(expect.stringContaining("common/models/tingen-beam with all its versions"));
    await vi.waitFor(() => expect(screen.queryByRole("region", { name: "Asset common/models/tingen-beam" })).toBeNull());
    expect(deleted).toEqual(["/api/v1/library/common/models/tingen-beam"]);
  });

  it("composes a twin package from assets put in the cart, and pushes its twin.yaml", async () => {
    const pushed: { url: string; body: unknown }[] = [];
    setup((url, init) => {
      if (!url.includes("/versions?") || init?.method !== "POST") return null;
      pushed.push({ url, body: init.body });
      return jsonResponse({ asset: asset("twins", "rig-kit", "user:ann"), version: { ...version(d1, ["latest"]), files: [] }, created: true }, 201);
    });
    await userEvent.click(await screen.findByRole("button", { name: "Add common/models/tingen-beam to the package" }));
    const form = screen.getByRole("form", { name: "Compose a package" });
    expect(screen.getByRole("button", { name: "Close the package" })).toBeInTheDocument();
    const alias = within(form).getByLabelText("Name of lib:common/models/tingen-beam@latest in the package");
    expect(alias).toHaveValue("tingen_beam");
    await userEvent.clear(alias);
    await userEvent.type(alias, "beam");
    await userEvent.type(within(form).getByLabelText("Package name"), "rig-kit");
    await userEvent.type(within(form).getByLabelText("Description"), "the rig");
    expect(within(form).getByLabelText("twin.yaml")).toHaveValue(
      '# A twin package composed on the Library page. Add parameters, devices, processors,\n' +
        "# connectors and services as docs/deployments.md describes, then push it.\n" +
        'description: "the rig"\nassets:\n  beam: "lib:common/models/tingen-beam@latest"\n' +
        'document:\n  version: "1.0"\n  name: "${deployment.name}"\n  description: "the rig"\n',
    );
    await userEvent.click(within(form).getByRole("button", { name: "Push package" }));
    expect(await within(form).findByRole("status")).toHaveTextContent("Pushed user:ann/twins/rig-kit");
    expect(pushed[0]!.url).toBe("/api/v1/library/user%3Aann/twins/rig-kit/versions?format=file&filename=twin.yaml&tag=latest");
    const body = pushed[0]!.body as File;
    expect(body.name).toBe("twin.yaml");
    const text = await new Promise<string>((resolve) => {
      const reader = new FileReader();
      reader.onload = () => resolve(String(reader.result));
      reader.readAsText(body);
    });
    expect(text).toContain('  beam: "lib:common/models/tingen-beam@latest"');
    // The row says it is in the cart; the cart outlives the page (the tab's sessionStorage).
    expect(screen.getByRole("table", { name: "Assets" })).toHaveTextContent("in the package");
    expect(JSON.parse(sessionStorage.getItem("twinlink.package-cart")!)).toEqual([{ alias: "beam", ref: "lib:common/models/tingen-beam@latest" }]);
  });

  it("points a tag at a version, and removes one", async () => {
    const calls: [string, string, unknown][] = [];
    setup((url, init) => {
      if (!url.includes("/tags/")) return null;
      calls.push([init?.method ?? "GET", url, init?.body ? JSON.parse(String(init.body)) : null]);
      return init?.method === "DELETE" ? new Response(null, { status: 204 }) : jsonResponse(asset("models", "tingen-beam"));
    });
    await userEvent.click(await screen.findByRole("button", { name: "common/models/tingen-beam" }));
    const form = await screen.findByRole("form", { name: "Set a tag" });
    await userEvent.type(within(form).getByLabelText("Tag"), "stable");
    await userEvent.selectOptions(within(form).getByLabelText("on version"), d1);
    await userEvent.click(within(form).getByRole("button", { name: "Set tag" }));
    await userEvent.click(screen.getByRole("button", { name: "Remove tag 1.0.0" }));
    await vi.waitFor(() => expect(calls).toHaveLength(2));
    expect(calls).toEqual([
      ["PUT", "/api/v1/library/common/models/tingen-beam/tags/stable", { version: d1 }],
      ["DELETE", "/api/v1/library/common/models/tingen-beam/tags/1.0.0", null],
    ]);
  });

  it("uploads the chosen file as the request body, with its scope, kind, name and tags", async () => {
    const pushed: { url: string; body: unknown }[] = [];
    setup((url, init) => {
      if (!url.includes("/versions?") || init?.method !== "POST") return null;
      pushed.push({ url, body: init.body });
      return jsonResponse({ asset: asset("models", "beam-model", "group:ntnu"), version: { ...version(d1, ["1.0.0", "latest"]), files: [{ path: "Beam Model.fmu", sha256: "1", size: 4, executable: false }] }, created: true }, 201);
    });
    await userEvent.click(await screen.findByRole("button", { name: "Upload" }));
    const form = screen.getByRole("form", { name: "Upload" });
    const file = new File(["FMU!"], "Beam Model.fmu");
    await userEvent.upload(within(form).getByLabelText("File or archive"), file);
    expect(within(form).getByLabelText("Name")).toHaveValue("beam-model");
    await userEvent.selectOptions(within(form).getByLabelText("Scope"), "group:ntnu");
    await userEvent.selectOptions(within(form).getByLabelText("Kind"), "models");
    await userEvent.type(within(form).getByLabelText("Tags"), "1.0.0");
    await userEvent.click(within(form).getByRole("button", { name: "Upload" }));
    expect(await within(form).findByRole("status")).toHaveTextContent("Uploaded: group:ntnu/models/beam-model");
    expect(pushed).toHaveLength(1);
    expect(pushed[0]!.url).toBe("/api/v1/library/group%3Antnu/models/beam-model/versions?format=file&filename=Beam+Model.fmu&tag=latest&tag=1.0.0");
    expect(pushed[0]!.body).toBe(file);
  });

  it("refuses a name or a tag the library would refuse, before uploading", async () => {
    const fetch = setup();
    await userEvent.click(await screen.findByRole("button", { name: "Upload" }));
    const form = screen.getByRole("form", { name: "Upload" });
    await userEvent.upload(within(form).getByLabelText("File or archive"), new File(["x"], "data.csv"));
    await userEvent.clear(within(form).getByLabelText("Name"));
    await userEvent.type(within(form).getByLabelText("Name"), "Bad Name");
    await userEvent.type(within(form).getByLabelText("Tags"), "v1 -bad");
    await userEvent.click(within(form).getByRole("button", { name: "Upload" }));
    expect(within(form).getByText(/starting with a letter or digit/)).toBeInTheDocument();
    expect(within(form).getByText(/"-bad" is not a tag/)).toBeInTheDocument();
    expect(urls(fetch).some((u) => u.includes("/versions?"))).toBe(false);
  });
});

describe("library helpers", () => {
  it("reads the upload format and a name from a file's name", () => {
    expect(formatOf("rig.zip")).toBe("zip");
    expect(formatOf("rig.TAR.GZ")).toBe("tgz");
    expect(formatOf("rig.tgz")).toBe("tgz");
    expect(formatOf("rig.tar")).toBe("tar");
    expect(formatOf("beam.fmu")).toBe("file");
    expect(nameFromFile("Tingen Beam.fmu")).toBe("tingen-beam");
    expect(nameFromFile("rig-1.2.tar.gz")).toBe("rig-1.2");
  });

  it("always moves latest with the tags typed", () => {
    expect(parseTags("1.0.0, stable")).toEqual({ tags: ["latest", "1.0.0", "stable"], bad: null });
    expect(parseTags("")).toEqual({ tags: ["latest"], bad: null });
  });

  it("names the scopes a user may use: their own, their groups', common", () => {
    expect(scopesOf({ username: "ann", groups: ["ntnu", "au"] })).toEqual(["user:ann", "group:ntnu", "group:au", "common"]);
  });

  it("saves an archive under the server's file name, else name and short digest", () => {
    expect(archiveName('attachment; filename="beam-111111111111.zip"', "beam", d1, "zip")).toBe("beam-111111111111.zip");
    expect(archiveName(null, "beam", d1, "tgz")).toBe("beam-111111111111.tar.gz");
  });
});
