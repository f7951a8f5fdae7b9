// A client of the live WebSocket GET /api/v1/live (docs/protocol.md, "Live streams for
// clients"): one connection, many subscriptions. It authenticates with a first message,
// subscribes once welcomed, reconnects with backoff and subscribes again after a reconnect,
// and stops for good when the server closes with 4401 (the token is no longer valid).

export interface Sample {
  time: number;
  values: Record<string, unknown>;
}

export interface SamplesMessage {
  type: "samples";
  sub: string;
  twin: string;
  stream: string;
  received: number;
  sent: number;
  samples: Sample[];
}

export interface DroppedMessage {
  type: "dropped";
  sub: string;
  messages: number;
  samples: number;
}

export type LiveState =
  | { kind: "connecting" }
  | { kind: "open" }
  | { kind: "reconnecting"; inMs: number; reason: string }
  | { kind: "unauthorized"; reason: string }
  | { kind: "closed" };

export interface SubscriptionSpec {
  twin: string;
  stream: string;
  signals?: string[];
  max_rate?: number;
}

export interface SubscriptionHandlers {
  onSamples: (message: SamplesMessage) => void;
  onDropped?: (message: DroppedMessage) => void;
  /** The server refused the subscription or ended it (twin deleted, access lost). */
  onError?: (message: string) => void;
}

/** What the client needs of a WebSocket; the browser's fits, and tests pass a fake. */
export interface WebSocketLike {
  readonly readyState: number;
  send(data: string): void;
  close(code?: number, reason?: string): void;
  onopen: ((event: unknown) => void) | null;
  onmessage: ((event: { data: unknown }) => void) | null;
  onclose: ((event: { code: number; reason: string }) => void) | null;
  onerror: ((event: unknown) => void) | null;
}

export interface LiveClientOptions {
  url: string;
  getToken: () => string | null;
  createSocket?: (url: string) => WebSocketLike;
  onState?: (state: LiveState) => void;
  /** The server clock (ns) at the welcome, to relate sample times to this browser's clock. */
  onServerTime?: (serverNs: number, localMs: number) => void;
  initialBackoffMs?: number;
  maxBackoffMs?: number;
}

export const CLOSE_UNAUTHORIZED = 4401;
const OPEN = 1;

/** The URL of the live WebSocket on the server that served this page. */
export function liveUrl(location: Pick<Location, "protocol" | "host"> = window.location): string {
  return `${location.protocol === "https:" ? "wss:" : "ws:"}//${location.host}/api/v1/live`;
}

export class LiveClient {
  private socket: WebSocketLike | null = null;
  private welcomed = false;
  private stopped = true;
  private retryTimer: ReturnType<typeof setTimeout> | null = null;
  private backoffMs: number;
  private nextId = 1;
  private readonly subscriptions = new Map<string, { spec: SubscriptionSpec; handlers: SubscriptionHandlers }>();

  constructor(private readonly options: LiveClientOptions) {
    this.backoffMs = options.initialBackoffMs ?? 500;
  }

  start(): void {
    if (!this.stopped) return;
    this.stopped = false;
    this.connect();
  }

  /** Close the connection and stop reconnecting; subscriptions are forgotten. */
  stop(): void {
    this.stopped = true;
    this.subscriptions.clear();
    if (this.retryTimer !== null) clearTimeout(this.retryTimer);
    this.retryTimer = null;
    const socket = this.socket;
    this.socket = null;
    if (socket) {
      socket.onclose = socket.onmessage = socket.onopen = socket.onerror = null;
      socket.close(1000, "done");
    }
    this.setState({ kind: "closed" });
  }

  /** Subscribe (now if connected, else once connected, and again after each reconnect);
   * answers the function that unsubscribes. */
  subscribe(spec: SubscriptionSpec, handlers: SubscriptionHandlers): () => void {
    const id = `s${this.nextId++}`;
    this.subscriptions.set(id, { spec, handlers });
    if (this.welcomed) this.sendSubscribe(id, spec);
    return () => {
      if (!this.subscriptions.delete(id)) return;
      if (this.welcomed) this.send({ op: "unsubscribe", id });
    };
  }

  private connect(): void {
    const token = this.options.getToken();
    if (!token) {
      this.stopped = true;
      this.setState({ kind: "unauthorized", reason: "not signed in" });
      return;
    }
    this.setState({ kind: "connecting" });
    const create = this.options.createSocket ?? ((url: string) => new WebSocket(url) as unknown as WebSocketLike);
    const socket = create(this.options.url);
    this.socket = socket;
    this.welcomed = false;
    socket.onopen = () => this.send({ op: "auth", token });
    socket.onmessage = (event) => this.receive(event.data);
    socket.onclose = (event) => this.closed(socket, event.code, event.reason);
    socket.onerror = () => undefined; // a close event always follows
  }

  private closed(socket: WebSocketLike, code: number, reason: string): void {
    if (socket !== this.socket) return;
    this.socket = null;
    this.welcomed = false;
    if (this.stopped) return;
    if (code === CLOSE_UNAUTHORIZED) {
      this.stopped = true;
      this.setState({ kind: "unauthorized", reason: reason || "the token is not valid" });
      return;
    }
    const jitter = 0.8 + Math.random() * 0.4;
    const inMs = Math.round(this.backoffMs * jitter);
    this.backoffMs = Math.min(this.backoffMs * 2, this.options.maxBackoffMs ?? 15_000);
    this.setState({ kind: "reconnecting", inMs, reason: reason || `connection closed (${code})` });
    this.retryTimer = setTimeout(() => {
      this.retryTimer = null;
      if (!this.stopped) this.connect();
    }, inMs);
  }

  private receive(data: unknown): void {
    let message: Record<string, unknown>;
    try {
      message = JSON.parse(String(data)) as Record<string, unknown>;
    } catch {
      return; // the server sends JSON only
    }
    const entry = typeof message.sub === "string" ? this.subscriptions.get(message.sub) : undefined;
    switch (message.type) {
      case "welcome":
        return this.welcome(message);
      case "samples":
        return entry?.handlers.onSamples(message as unknown as SamplesMessage);
      case "dropped":
        return entry?.handlers.onDropped?.(message as unknown as DroppedMessage);
      case "error":
      case "unsubscribed":
        return this.refused(message);
    }
  }

  private welcome(message: Record<string, unknown>): void {
    this.welcomed = true;
    this.backoffMs = this.options.initialBackoffMs ?? 500;
    if (typeof message.server_time === "number") this.options.onServerTime?.(message.server_time, Date.now());
    this.setState({ kind: "open" });
    for (const [id, { spec }] of this.subscriptions) this.sendSubscribe(id, spec);
  }

  /** An `error` about a subscription, or an `unsubscribed` the client did not ask for. */
  private refused(message: Record<string, unknown>): void {
    const id = typeof message.id === "string" ? message.id : null;
    const entry = id ? this.subscriptions.get(id) : undefined;
    if (!entry || !id) return;
    const text = String(message.message ?? message.reason ?? "refused by the server");
    this.subscriptions.delete(id);
    entry.handlers.onError?.(text);
  }

  private sendSubscribe(id: string, spec: SubscriptionSpec): void {
    this.send({ op: "subscribe", id, ...spec });
  }

  private send(message: Record<string, unknown>): void {
    if (this.socket && this.socket.readyState === OPEN) this.socket.send(JSON.stringify(message));
  }

  private setState(state: LiveState): void {
    this.options.onState?.(state);
  }
}
