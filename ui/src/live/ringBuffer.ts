/** A fixed-size ring of (time, value) pairs in preallocated Float64Arrays: pushing never
 * allocates, and once full each push overwrites the oldest pair. Times are seconds since the
 * epoch (a float64 keeps them to well under a microsecond). Pairs are expected in time order;
 * a late one is kept where it arrives (lookups by time then are approximate around it). */
export class RingBuffer {
  readonly capacity: number;
  private readonly times: Float64Array;
  private readonly values: Float64Array;
  /** Index of the oldest pair. */
  private head = 0;
  private count = 0;
  /** Pairs pushed since the buffer was made: pair number n (0-based) is still held when
   * n >= pushed - length. */
  pushed = 0;
  /** Bumped when pairs are removed or reordered other than by overwriting the oldest, so a
   * reader that follows `pushed` knows to start over. */
  generation = 0;

  constructor(capacity: number) {
    if (!Number.isInteger(capacity) || capacity < 1) throw new RangeError("capacity must be a positive integer");
    this.capacity = capacity;
    this.times = new Float64Array(capacity);
    this.values = new Float64Array(capacity);
  }

  get length(): number {
    return this.count;
  }

  push(time: number, value: number): void {
    const slot = (this.head + this.count) % this.capacity;
    this.times[slot] = time;
    this.values[slot] = value;
    if (this.count < this.capacity) this.count++;
    else this.head = (this.head + 1) % this.capacity;
    this.pushed++;
  }

  clear(): void {
    this.head = 0;
    this.count = 0;
    this.generation++;
  }

  /** The i-th oldest time (0 = oldest). */
  timeAt(i: number): number {
    return this.times[(this.head + i) % this.capacity] as number;
  }

  valueAt(i: number): number {
    return this.values[(this.head + i) % this.capacity] as number;
  }

  lastTime(): number | undefined {
    return this.count ? this.timeAt(this.count - 1) : undefined;
  }

  firstTime(): number | undefined {
    return this.count ? this.timeAt(0) : undefined;
  }

  /** The index of the first pair whose time is at least `time` (binary search). */
  lowerBound(time: number): number {
    let lo = 0;
    let hi = this.count;
    while (lo < hi) {
      const mid = (lo + hi) >>> 1;
      if (this.timeAt(mid) < time) lo = mid + 1;
      else hi = mid;
    }
    return lo;
  }

  /** Put older pairs (in time order) before the ones held: for history loaded after live
   * data started to arrive. Only pairs older than the oldest held one are taken. */
  prependOlder(times: ArrayLike<number>, values: ArrayLike<number>): void {
    const oldest = this.firstTime() ?? Infinity;
    let take = 0;
    while (take < times.length && (times[take] as number) < oldest) take++;
    if (take === 0) return;
    const heldTimes = new Float64Array(this.count);
    const heldValues = new Float64Array(this.count);
    for (let i = 0; i < this.count; i++) {
      heldTimes[i] = this.timeAt(i);
      heldValues[i] = this.valueAt(i);
    }
    this.clear();
    for (let i = 0; i < take; i++) this.push(times[i] as number, values[i] as number);
    for (let i = 0; i < heldTimes.length; i++) this.push(heldTimes[i] as number, heldValues[i] as number);
    this.generation++;
  }
}
