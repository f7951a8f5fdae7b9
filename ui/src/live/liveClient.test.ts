import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";
import { FakeSocket, fakeSocketFactory } from "./fakeSocket";
import { LiveClient, liveUrl, type LiveState } from "./liveClient";

let states: LiveState[];

function makeClient(token: string | null = "tl_secret") {
  states = [];
  return new LiveClient({
    url: "ws://host/api/v1/live",
    getToken: () => token,
    createSocket: fakeSocketFactory,
    onState: (s) => states.push(s),
    initialBackoffMs: 100,
    maxBackoffMs: 1000,
  });
}

const SPEC = { twin: "tingen", stream: "telemetry", signals: ["Cantilever_Angle_radians"] };

beforeEach(() => {
  FakeSocket.instances = [];
  vi.useFakeTimers();
});
afterEach(() => vi.useRealTimers());

describe("LiveClient", () => {
  it("authenticates with the first message and subscribes once welcomed", () => {
    const client = makeClient();
    const onSamples = vi.fn();
    client.subscribe(SPEC, { onSamples });
    client.start();
    const socket = FakeSocket.latest();
    expect(socket.url).toBe("ws://host/api/v1/live");
    socket.open();
    expect(socket.sent).toEqual([{ op: "auth", token: "tl_secret" }]);
    socket.welcome();
    expect(states.at(-1)).toEqual({ kind: "open" });
    expect(socket.sent[1]).toEqual({ op: "subscribe", id: "s1", ...SPEC });

    const samples = { type: "samples", sub: "s1", stream: "telemetry", received: 1, sent: 2, samples: [{ time: 1, values: { x: 1 } }] };
    socket.receive(samples);
    socket.receive({ ...samples, sub: "other" });
    expect(onSamples).toHaveBeenCalledTimes(1);
    expect(onSamples.mock.calls[0]![0]).toMatchObject({ sub: "s1" });
  });

  it("subscribes at once when already welcomed, and unsubscribes", () => {
    const client = makeClient();
    client.start();
    const socket = FakeSocket.latest();
    socket.open();
    socket.welcome();
    const stop = client.subscribe({ ...SPEC, max_rate: 50 }, { onSamples: vi.fn() });
    expect(socket.ops("subscribe")).toEqual([{ op: "subscribe", id: "s1", ...SPEC, max_rate: 50 }]);
    stop();
    stop();
    expect(socket.ops("unsubscribe")).toEqual([{ op: "unsubscribe", id: "s1" }]);
  });

  it("reconnects with growing backoff and subscribes again after the reconnect", () => {
    const client = makeClient();
    client.subscribe(SPEC, { onSamples: vi.fn() });
    client.start();
    FakeSocket.latest().open();
    FakeSocket.latest().welcome();
    FakeSocket.latest().drop(1012, "restarting");
    expect(states.at(-1)).toMatchObject({ kind: "reconnecting", reason: "restarting" });
    expect(FakeSocket.instances).toHaveLength(1);
    vi.advanceTimersByTime(120); // first backoff: 100 ms ± 20 %
    expect(FakeSocket.instances).toHaveLength(2);
    const second = FakeSocket.latest();
    second.drop(); // never opened: the backoff doubles
    vi.advanceTimersByTime(159);
    expect(FakeSocket.instances).toHaveLength(2);
    vi.advanceTimersByTime(90);
    const third = FakeSocket.latest();
    expect(FakeSocket.instances).toHaveLength(3);
    third.open();
    third.welcome();
    expect(third.sent).toEqual([
      { op: "auth", token: "tl_secret" },
      { op: "subscribe", id: "s1", ...SPEC },
    ]);
  });

  it("stops for good when the server closes with 4401", () => {
    const client = makeClient();
    client.start();
    FakeSocket.latest().open();
    FakeSocket.latest().drop(4401, "token expired");
    expect(states.at(-1)).toEqual({ kind: "unauthorized", reason: "token expired" });
    vi.advanceTimersByTime(60_000);
    expect(FakeSocket.instances).toHaveLength(1);
  });

  it("does not connect without a token", () => {
    makeClient(null).start();
    expect(FakeSocket.instances).toHaveLength(0);
    expect(states.at(-1)).toEqual({ kind: "unauthorized", reason: "not signed in" });
  });

  it("hands subscription errors, drops and ends to the subscription's handlers", () => {
    const client = makeClient();
    const onError = vi.fn();
    const onDropped = vi.fn();
    client.subscribe(SPEC, { onSamples: vi.fn(), onError, onDropped });
    client.subscribe({ ...SPEC, twin: "gone" }, { onSamples: vi.fn(), onError });
    client.start();
    const socket = FakeSocket.latest();
    socket.open();
    socket.welcome();
    socket.receive({ type: "dropped", sub: "s1", messages: 3, samples: 1200 });
    expect(onDropped).toHaveBeenCalledWith({ type: "dropped", sub: "s1", messages: 3, samples: 1200 });
    socket.receive({ type: "error", op: "subscribe", id: "s2", message: "no twin 'gone'" });
    socket.receive({ type: "unsubscribed", id: "s1", reason: "no twin 'tingen'" });
    expect(onError.mock.calls).toEqual([["no twin 'gone'"], ["no twin 'tingen'"]]);
  });

  it("closes the socket and stops reconnecting when stopped", () => {
    const client = makeClient();
    client.start();
    const socket = FakeSocket.latest();
    socket.open();
    client.stop();
    expect(socket.closedWith).toEqual({ code: 1000, reason: "done" });
    expect(states.at(-1)).toEqual({ kind: "closed" });
    vi.advanceTimersByTime(60_000);
    expect(FakeSocket.instances).toHaveLength(1);
  });

  it("builds the URL from the page's location", () => {
    expect(liveUrl({ protocol: "https:", host: "twins.example:8443" })).toBe("wss://twins.example:8443/api/v1/live");
    expect(liveUrl({ protocol: "http:", host: "127.0.0.1:8000" })).toBe("ws://127.0.0.1:8000/api/v1/live");
  });
});
