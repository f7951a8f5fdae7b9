/** Rolling statistics of one live stream: delay (sent − sample time), platform time
 * (sent − received), samples per second and dropped notices, over the last few seconds. */

export interface Percentiles {
  median: number;
  p99: number;
  count: number;
}

/** A bounded window of (arrival time, value) observations; old ones fall out by age or, past
 * `capacity`, by count. Preallocated: adding never allocates. */
export class ObservationWindow {
  private readonly at: Float64Array;
  private readonly values: Float64Array;
  private head = 0;
  private count = 0;

  constructor(readonly capacity = 4096) {
    this.at = new Float64Array(capacity);
    this.values = new Float64Array(capacity);
  }

  add(nowMs: number, value: number): void {
    const slot = (this.head + this.count) % this.capacity;
    this.at[slot] = nowMs;
    this.values[slot] = value;
    if (this.count < this.capacity) this.count++;
    else this.head = (this.head + 1) % this.capacity;
  }

  /** Median and 99th percentile (nearest rank) of the values added in the last `spanMs`. */
  percentiles(nowMs: number, spanMs: number): Percentiles | null {
    const recent: number[] = [];
    for (let i = 0; i < this.count; i++) {
      const slot = (this.head + i) % this.capacity;
      if ((this.at[slot] as number) >= nowMs - spanMs) recent.push(this.values[slot] as number);
    }
    if (recent.length === 0) return null;
    const sorted = Float64Array.from(recent).sort();
    return { median: rank(sorted, 0.5), p99: rank(sorted, 0.99), count: sorted.length };
  }

  /** The sum of the values added in the last `spanMs`. */
  sum(nowMs: number, spanMs: number): number {
    let total = 0;
    for (let i = 0; i < this.count; i++) {
      const slot = (this.head + i) % this.capacity;
      if ((this.at[slot] as number) >= nowMs - spanMs) total += this.values[slot] as number;
    }
    return total;
  }
}

function rank(sorted: Float64Array, q: number): number {
  const index = Math.min(sorted.length - 1, Math.max(0, Math.ceil(q * sorted.length) - 1));
  return sorted[index] as number;
}

export interface StreamStatsSnapshot {
  /** sent − sample time, ms. */
  delay: Percentiles | null;
  /** sent − received: the time spent in the platform, ms. */
  platform: Percentiles | null;
  samplesPerSecond: number;
  droppedSamples: number;
  droppedMessages: number;
}

const NS_PER_MS = 1e6;
/** Per message, at most this many samples' delays are recorded (spread over the batch), so a
 * 10 000 samples/s stream costs no more than a slow one. */
const DELAY_SAMPLES_PER_MESSAGE = 16;

export class StreamStats {
  private readonly delay = new ObservationWindow();
  private readonly platform = new ObservationWindow(1024);
  private readonly received = new ObservationWindow(1024);
  droppedSamples = 0;
  droppedMessages = 0;
  private firstMessageMs: number | null = null;

  constructor(private readonly spanMs = 5000) {}

  /** Record one `samples` message: its server times (ns) and its sample times (ns). */
  addMessage(nowMs: number, receivedNs: number, sentNs: number, sampleTimesNs: ArrayLike<number>): void {
    const n = sampleTimesNs.length;
    this.firstMessageMs ??= nowMs;
    this.platform.add(nowMs, (sentNs - receivedNs) / NS_PER_MS);
    this.received.add(nowMs, n);
    const step = Math.max(1, Math.ceil(n / DELAY_SAMPLES_PER_MESSAGE));
    for (let i = n - 1; i >= 0; i -= step) {
      this.delay.add(nowMs, (sentNs - (sampleTimesNs[i] as number)) / NS_PER_MS);
    }
  }

  addDropped(messages: number, samples: number): void {
    this.droppedMessages += messages;
    this.droppedSamples += samples;
  }

  snapshot(nowMs: number): StreamStatsSnapshot {
    // Right after the start the window is not full yet: divide by the time there was.
    const elapsedMs = this.firstMessageMs === null ? this.spanMs : nowMs - this.firstMessageMs;
    const spanMs = Math.min(this.spanMs, Math.max(1000, elapsedMs));
    return {
      delay: this.delay.percentiles(nowMs, this.spanMs),
      platform: this.platform.percentiles(nowMs, this.spanMs),
      samplesPerSecond: this.received.sum(nowMs, spanMs) / (spanMs / 1000),
      droppedSamples: this.droppedSamples,
      droppedMessages: this.droppedMessages,
    };
  }
}
