// What the Live tab has received: one ring buffer per chosen signal, statistics per stream,
// and the count of samples received. Messages only append here; drawing reads it once per
// animation frame.
import type { DownsampleAnswer, TimedSample } from "../api/history";
import type { TimedValue } from "../components/charts/steps";
import { decimateMinMax, type AlignedSeries } from "./decimate";
import { LiveDecimator } from "./liveDecimator";
import { StreamStats } from "./delayStats";
import type { DroppedMessage, SamplesMessage } from "./liveClient";
import { RingBuffer } from "./ringBuffer";
import { refKey, type SignalRef } from "./selection";

/** All buffers of a tab together hold at most this many points (16 bytes each). */
const POINT_BUDGET = 1 << 21;
const MIN_CAPACITY = 1 << 16;
const MAX_CAPACITY = 1 << 20;
/** A window that fits this rate needs no `max_rate`: few devices send more per stream (one
 * that does shows only the newest part of a long window). */
const NO_LIMIT_RATE = 20_000;

export function capacityPerSignal(signalCount: number): number {
  return Math.max(MIN_CAPACITY, Math.min(MAX_CAPACITY, Math.floor(POINT_BUDGET / Math.max(1, signalCount))));
}

/** The `max_rate` that lets a whole window fit in the buffers, or undefined when any rate a
 * device may send fits anyway. */
export function maxRateFor(signalCount: number, windowS: number): number | undefined {
  const rate = Math.floor(capacityPerSignal(signalCount) / windowS);
  return rate < NO_LIMIT_RATE ? rate : undefined;
}

function numeric(value: unknown): number | null {
  if (typeof value === "number") return value;
  if (typeof value === "boolean") return value ? 1 : 0;
  return null;
}

export class LiveStore {
  readonly refs: SignalRef[];
  private readonly buffers: RingBuffer[];
  private readonly decimator: LiveDecimator;
  private readonly byStream = new Map<string, { signal: string; buffer: RingBuffer; index: number }[]>();
  /** Per signal, its last sample before the window when the subscription started (seconds). */
  private seeds: (TimedValue | null)[];
  readonly stats = new Map<string, StreamStats>();
  /** Live samples received since the store was made (history backfill not counted). */
  points = 0;
  /** Bumped on every change, so a drawing loop knows whether to draw again. */
  version = 0;

  constructor(refs: SignalRef[], capacity = capacityPerSignal(refs.length)) {
    this.refs = refs;
    this.buffers = refs.map(() => new RingBuffer(capacity));
    this.decimator = new LiveDecimator(this.buffers);
    this.seeds = refs.map(() => null);
    refs.forEach((ref, i) => {
      const list = this.byStream.get(ref.stream) ?? [];
      list.push({ signal: ref.signal, buffer: this.buffers[i] as RingBuffer, index: i });
      this.byStream.set(ref.stream, list);
      if (!this.stats.has(ref.stream)) this.stats.set(ref.stream, new StreamStats());
    });
  }

  addSamples(message: SamplesMessage, nowMs: number = Date.now()): void {
    const targets = this.byStream.get(message.stream);
    if (!targets) return;
    const samples = message.samples;
    const times = new Float64Array(samples.length);
    for (let i = 0; i < samples.length; i++) {
      const sample = samples[i] as SamplesMessage["samples"][number];
      times[i] = sample.time;
      const seconds = sample.time / 1e9;
      for (const { signal, buffer } of targets) {
        const value = numeric(sample.values[signal]);
        if (value !== null) buffer.push(seconds, value);
      }
    }
    this.points += samples.length;
    this.stats.get(message.stream)?.addMessage(nowMs, message.received, message.sent, times);
    this.version++;
  }

  addDropped(stream: string, message: DroppedMessage): void {
    this.stats.get(stream)?.addDropped(message.messages, message.samples);
    this.version++;
  }

  /** History from /downsample, put before the live data already held. */
  backfill(stream: string, answer: DownsampleAnswer): void {
    for (const { signal, buffer } of this.byStream.get(stream) ?? []) {
      const series = answer.signals[signal];
      if (!series) continue;
      buffer.prependOlder(series.time.map((t) => t / 1e9), series.value);
    }
    this.version++;
  }

  /** The last sample before the window of each signal of `stream`, from the API (ns). */
  seed(stream: string, samples: Record<string, TimedSample>): void {
    for (const { signal, index } of this.byStream.get(stream) ?? []) {
      const sample = samples[signal];
      if (sample) this.seeds[index] = { time: sample.time / 1e9, value: sample.value };
    }
    this.version++;
  }

  /** Per signal, its last sample before `time` (seconds): the newest one held before it, else
   * the seed (older than anything held). A full buffer has dropped samples, maybe newer than
   * the seed: then nothing is known. */
  before(time: number): (TimedValue | null)[] {
    return this.buffers.map((buffer, i) => {
      const at = buffer.lowerBound(time) - 1;
      if (at >= 0) {
        const value = buffer.valueAt(at);
        return Number.isNaN(value) ? null : { time: buffer.timeAt(at), value };
      }
      const seed = this.seeds[i];
      return seed && seed.time < time && buffer.length < buffer.capacity ? seed : null;
    });
  }

  /** Forget the data (not the count of samples received): before subscribing again. */
  clearData(): void {
    for (const buffer of this.buffers) buffer.clear();
    this.seeds = this.refs.map(() => null);
    for (const stream of this.stats.keys()) this.stats.set(stream, new StreamStats());
    this.version++;
  }

  /** The newest sample time held, in seconds. */
  latestTime(): number | undefined {
    let latest: number | undefined;
    for (const buffer of this.buffers) {
      const t = buffer.lastTime();
      if (t !== undefined && (latest === undefined || t > latest)) latest = t;
    }
    return latest;
  }

  /** The chart's data over [xMin, xMax] (seconds), decimated to `columns` pixel columns
   * (reads every sample in the range: for a zoomed view). */
  frame(xMin: number, xMax: number, columns: number): AlignedSeries {
    return decimateMinMax(this.buffers, xMin, xMax, columns);
  }

  /** The same for the window of `windowS` seconds ending at `end`, done incrementally from
   * one call to the next (for a window that follows live data). */
  followFrame(end: number, windowS: number, columns: number): AlignedSeries {
    return this.decimator.frame(end, windowS, columns);
  }

  labels(): string[] {
    return this.refs.map(refKey).map((key) => key.replace(":", "/"));
  }
}
