import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen, within } from "@testing-library/react";
import { jsonResponse, mockFetch, problem } from "../../test/fetch";
import { FmuPanel } from "./FmuPanel";
import { fakeApi } from "./test/api";
import { tingenFmu } from "./test/tingen";

afterEach(() => vi.unstubAllGlobals());

const wait = { timeout: 4000 };
const isUpload = (url: string, init?: RequestInit) => init?.method === "PUT" && url.startsWith("/api/v1/twins/tingen/fmus/");

function upload(fileName = "Tingen.fmu") {
  const file = new File([new Uint8Array([80, 75, 3, 4])], fileName, { type: "" });
  fireEvent.change(screen.getByLabelText("FMU file"), { target: { files: [file] } });
  fireEvent.click(screen.getByRole("button", { name: "Upload FMU" }));
  return file;
}

describe("FmuPanel", () => {
  it("lists the FMUs and shows one's variables", async () => {
    mockFetch(fakeApi());
    render(<FmuPanel slug="tingen" editable={false} version={0} onUploaded={() => {}} />);
    fireEvent.click(await screen.findByRole("button", { name: "Variables of Tingen.fmu" }, wait));
    const table = await screen.findByRole("table", { name: "Variables of Tingen.fmu" }, wait);
    const force = within(table).getByText("F").closest("tr")!;
    expect(force).toHaveTextContent("input");
    expect(force).toHaveTextContent("N");
    expect(force).toHaveTextContent("-50");
    expect(within(table).getByText("zeta").closest("tr")).toHaveTextContent("tunable");
    expect(screen.queryByLabelText("FMU file")).not.toBeInTheDocument(); // viewers do not upload
  });

  it("uploads the file's bytes as application/octet-stream", async () => {
    const fetch = mockFetch(fakeApi((url, init) => (isUpload(url, init) ? jsonResponse(tingenFmu, 201) : null)));
    const onUploaded = vi.fn();
    render(<FmuPanel slug="tingen" editable version={0} onUploaded={onUploaded} />);
    const file = upload();
    expect(await screen.findByRole("status", {}, wait)).toHaveTextContent("Uploaded Tingen.fmu: FMI 2.0, 1 input, 3 outputs, 7 parameters.");
    const [url, init] = fetch.mock.calls.find(([u, i]) => isUpload(String(u), i))!;
    expect(url).toBe("/api/v1/twins/tingen/fmus/Tingen.fmu");
    expect(init?.body).toBe(file);
    expect((init?.headers as Record<string, string>)["Content-Type"]).toBe("application/octet-stream");
    expect(onUploaded).toHaveBeenCalledWith(tingenFmu);
  });

  it.each([
    [413, "the upload is larger than 200 MB (TWINLINK_FMU_MAX_MB)", "The file is larger than this server accepts"],
    [422, "not a usable FMU: modelDescription.xml is missing", "The server cannot use this file"],
  ])("says why an upload was refused (%i)", async (status, detail, lead) => {
    mockFetch(fakeApi((url, init) => (isUpload(url, init) ? problem(status, detail) : null)));
    render(<FmuPanel slug="tingen" editable version={0} onUploaded={() => {}} />);
    upload("broken.fmu");
    const alert = await screen.findByRole("alert", {}, wait);
    expect(alert).toHaveTextContent(`(${status})`);
    expect(alert).toHaveTextContent(`${lead}: ${detail}`);
  });
});
