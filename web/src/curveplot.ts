// The graph editor's plot: the mapping between frames/values and canvas
// pixels, grid steps, curve colours and hit tests. No DOM and no requests:
// grapheditor.ts draws with it and turns pointer gestures into edits.

import type { CurveInfo } from './api';

/** The part of the (frame, value) plane shown. */
export interface View {
  x0: number;
  x1: number;
  y0: number;
  y1: number;
}

/** A key of a shown curve. */
export interface KeyHit {
  curve: CurveInfo;
  index: number;
}

export class Plot {
  constructor(
    public view: View,
    public width: number,
    public height: number,
  ) {}

  /** Pixels per frame and per value unit. */
  get sx(): number {
    return this.width / Math.max(1e-9, this.view.x1 - this.view.x0);
  }
  get sy(): number {
    return this.height / Math.max(1e-12, this.view.y1 - this.view.y0);
  }
  px(frame: number): number {
    return (frame - this.view.x0) * this.sx;
  }
  py(value: number): number {
    return this.height - (value - this.view.y0) * this.sy;
  }
  frameAt(px: number): number {
    return this.view.x0 + px / this.sx;
  }
  valueAt(py: number): number {
    return this.view.y0 + (this.height - py) / this.sy;
  }

  /** The two ends of a key's tangent handles, `length` pixels from the key (curves only). */
  handles(c: CurveInfo, i: number, length: number): { in: [number, number]; out: [number, number] } | null {
    const inS = c.inSlopes?.[i];
    const outS = c.outSlopes?.[i];
    if (inS === undefined || outS === undefined) return null;
    const kx = this.px(c.frames[i]!);
    const ky = this.py(c.values[i]!);
    const end = (slope: number, sign: number): [number, number] => {
      const dx = this.sx;
      const dy = -slope * this.sy;
      const n = Math.hypot(dx, dy) || 1;
      return [kx + (sign * dx * length) / n, ky + (sign * dy * length) / n];
    };
    return { in: end(inS, -1), out: end(outS, 1) };
  }
}

/** A grid step near `span / count` among 1, 2, 5 times a power of ten. */
export function niceStep(span: number, count: number, integer = false): number {
  const raw = Math.max(span, 1e-12) / Math.max(1, count);
  const p = Math.pow(10, Math.floor(Math.log10(raw)));
  let step = p;
  for (const m of [1, 2, 5, 10]) {
    step = m * p;
    if (step >= raw) break;
  }
  return integer ? Math.max(1, Math.round(step)) : step;
}

/** The lines of a grid step over [a, b]. */
export function gridLines(a: number, b: number, step: number): number[] {
  const out: number[] = [];
  if (!(step > 0) || !Number.isFinite(a) || !Number.isFinite(b)) return out;
  for (let v = Math.ceil(a / step) * step; v <= b && out.length < 500; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return out;
}

/** A curve's colour: x y z red green blue as Maya draws them, w grey, a scalar by its place. */
export function curveColour(c: CurveInfo, index: number): string {
  const axis = /(?:[XYZW]|\.[xyzw])$/.exec(c.label)?.[0]?.slice(-1).toLowerCase();
  if (axis === 'x') return '#e0605a';
  if (axis === 'y') return '#6ccf6a';
  if (axis === 'z') return '#5a9be6';
  if (axis === 'w') return '#b0b0b0';
  const palette = ['#e6c25a', '#c57ae0', '#5ad2d2', '#e69a5a', '#9ad25a'];
  return palette[index % palette.length]!;
}

/** The bounds of the keys and samples of `curves` (null: nothing to bound). */
export function bounds(curves: CurveInfo[], keysOnly: (c: CurveInfo) => number[] | null): View | null {
  let x0 = Infinity;
  let x1 = -Infinity;
  let y0 = Infinity;
  let y1 = -Infinity;
  for (const c of curves) {
    const only = keysOnly(c);
    const idx = only ?? c.frames.map((_, i) => i);
    for (const i of idx) {
      x0 = Math.min(x0, c.frames[i]!);
      x1 = Math.max(x1, c.frames[i]!);
      y0 = Math.min(y0, c.values[i]!);
      y1 = Math.max(y1, c.values[i]!);
    }
    if (only) continue;
    const s = c.samples;
    for (let i = 0; i < s.frames.length; ++i) {
      if (s.frames[i]! < x0 || s.frames[i]! > x1) continue;
      y0 = Math.min(y0, s.values[i]!);
      y1 = Math.max(y1, s.values[i]!);
    }
  }
  if (!Number.isFinite(x0)) return null;
  return { x0, x1, y0, y1 };
}

/** `b` grown by a margin on every side, at least `minFrames` wide and some value units tall. */
export function padded(b: View, minFrames = 10): View {
  let { x0, x1, y0, y1 } = b;
  if (x1 - x0 < minFrames) {
    const c = (x0 + x1) / 2;
    x0 = c - minFrames / 2;
    x1 = c + minFrames / 2;
  }
  const tall = Math.max(y1 - y0, Math.abs(y0) * 0.1, Math.abs(y1) * 0.1, 0.1);
  if (y1 - y0 < tall) {
    const c = (y0 + y1) / 2;
    y0 = c - tall / 2;
    y1 = c + tall / 2;
  }
  const mx = (x1 - x0) * 0.08;
  const my = (y1 - y0) * 0.12;
  return { x0: x0 - mx, x1: x1 + mx, y0: y0 - my, y1: y1 + my };
}

/** The value of a curve's samples at `frame` (linear between samples; null outside them). */
export function sampleAt(c: CurveInfo, frame: number): number | null {
  const f = c.samples.frames;
  const v = c.samples.values;
  if (!f.length || frame < f[0]! || frame > f[f.length - 1]!) return null;
  let lo = 0;
  let hi = f.length - 1;
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (f[mid]! <= frame) lo = mid;
    else hi = mid;
  }
  const span = f[hi]! - f[lo]!;
  const t = span > 0 ? (frame - f[lo]!) / span : 0;
  return v[lo]! + (v[hi]! - v[lo]!) * t;
}
