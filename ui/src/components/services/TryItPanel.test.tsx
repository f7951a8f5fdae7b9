import { afterEach, describe, expect, it, vi } from "vitest";
import { fireEvent, render, screen } from "@testing-library/react";
import { TryItPanel } from "./TryItPanel";
import { setToken } from "../../api/client";
import { jsonResponse, mockFetch } from "../../test/fetch";

afterEach(() => vi.unstubAllGlobals());

const service = { name: "historian", methods: ["GET", "POST"], health_path: "signals" };

describe("TryItPanel", () => {
  it("sends the request through the gateway with the token and pretty-prints JSON", async () => {
    setToken("tl_abc");
    const fetch = mockFetch(() => jsonResponse({ data: [{ name: "hook_load" }] }));
    render(<TryItPanel slug="ilmatar-k16052" service={service} />);
    fireEvent.change(screen.getByLabelText("Path"), { target: { value: "/timeseries?signal=load" } });
    fireEvent.click(screen.getByRole("button", { name: "Send" }));
    const answer = await screen.findByTestId("try-it-answer");
    const [url, init] = fetch.mock.calls[0]!;
    expect(url).toBe("/twins/ilmatar-k16052/services/historian/timeseries?signal=load");
    expect(init?.method).toBe("GET");
    expect((init?.headers as Record<string, string>).Authorization).toBe("Bearer tl_abc");
    expect(answer).toHaveTextContent("200");
    expect(answer).toHaveTextContent("application/json");
    expect(answer.querySelector("pre")?.textContent).toContain('"name": "hook_load"');
  });

  it("sends a JSON body and shows a non-2xx answer with its status", async () => {
    const fetch = mockFetch(() =>
      jsonResponse(
        { type: "about:blank", status: 502, detail: "the service could not be reached", source: "gateway", code: "upstream_connect" },
        502,
        "application/problem+json",
      ),
    );
    render(<TryItPanel slug="tingen" service={service} />);
    fireEvent.change(screen.getByLabelText("Method"), { target: { value: "POST" } });
    fireEvent.change(screen.getByLabelText("Path"), { target: { value: "write" } });
    fireEvent.change(screen.getByLabelText("JSON body"), { target: { value: '{"value": 1}' } });
    fireEvent.click(screen.getByRole("button", { name: "Send" }));
    const answer = await screen.findByTestId("try-it-answer");
    const [url, init] = fetch.mock.calls[0]!;
    expect(url).toBe("/twins/tingen/services/historian/write");
    expect(init?.method).toBe("POST");
    expect(init?.body).toBe('{"value":1}');
    expect(answer.querySelector(".status")).toHaveTextContent("502");
    expect(answer.querySelector(".status")).toHaveClass("status-bad");
    expect(answer).toHaveTextContent("the service could not be reached");
  });

  it("refuses a body that is not JSON without sending", async () => {
    const fetch = mockFetch(() => jsonResponse({}));
    render(<TryItPanel slug="tingen" service={service} />);
    fireEvent.change(screen.getByLabelText("Method"), { target: { value: "POST" } });
    fireEvent.change(screen.getByLabelText("JSON body"), { target: { value: "{nope" } });
    fireEvent.click(screen.getByRole("button", { name: "Send" }));
    expect(await screen.findByRole("alert")).toHaveTextContent("not valid JSON");
    expect(fetch).not.toHaveBeenCalled();
  });

  it("truncates a huge text answer", async () => {
    mockFetch(() => new Response("x".repeat(150_000), { status: 200, headers: { "Content-Type": "text/plain" } }));
    render(<TryItPanel slug="tingen" service={service} />);
    fireEvent.click(screen.getByRole("button", { name: "Send" }));
    const answer = await screen.findByTestId("try-it-answer");
    expect(answer).toHaveTextContent("only its first 100,000 characters");
    expect(answer.querySelector("pre")?.textContent).toHaveLength(100_000);
  });
});
