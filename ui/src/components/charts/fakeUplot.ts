// A stand-in for uPlot in tests: jsdom has no canvas. Use with
// vi.mock("uplot", async () => (await import("../../components/charts/fakeUplot")).fakeUplotModule)
import type uPlot from "uplot";

export class FakeUplot {
  static instances: FakeUplot[] = [];
  static paths = { stepped: () => () => null };
  readonly opts: uPlot.Options;
  data: uPlot.AlignedData;
  xRange: [number, number] | null = null;
  destroyed = false;
  width: number;
  bbox = { left: 0, top: 0, width: 800, height: 300 };
  select = { left: 0, top: 0, width: 0, height: 0 };

  constructor(opts: uPlot.Options, data: uPlot.AlignedData) {
    this.opts = opts;
    this.data = data;
    this.width = opts.width;
    FakeUplot.instances.push(this);
  }

  setData(data: uPlot.AlignedData): void {
    this.data = data;
  }

  setScale(_key: string, range: { min: number; max: number }): void {
    this.xRange = [range.min, range.max];
  }

  batch(fn: (self: FakeUplot) => void): void {
    fn(this);
  }

  setSize(size: { width: number }): void {
    this.width = size.width;
  }

  setSelect(select: { left: number; top: number; width: number; height: number }): void {
    this.select = select;
  }

  posToVal(left: number): number {
    return left;
  }

  destroy(): void {
    this.destroyed = true;
  }

  /** Pretend the user dragged over [left, left + width] pixels (the fake's pixels are values). */
  drag(left: number, width: number): void {
    this.select = { left, top: 0, width, height: 100 };
    for (const hook of this.opts.hooks?.setSelect ?? []) hook?.(this as unknown as uPlot);
  }
}

export const fakeUplotModule = { default: FakeUplot };
