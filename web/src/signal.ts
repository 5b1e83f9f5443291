// A typed signal: one named event of the store (store.ts) that the views
// subscribe to, as three.js's editor does with its `signals`. Dispatching
// calls every listener in the order they were added, synchronously, with
// the new value.

export type Listener<T> = (value: T) => void;

export class Signal<T> {
  private listeners: Listener<T>[] = [];

  /**
   * `report` receives what a listener throws: one failing view never keeps
   * the others from being told (the store passes the status bar's `caught`).
   */
  constructor(private readonly report: (e: unknown) => void = (e) => console.error(e)) {}

  /** Calls `f` at every dispatch from now on; returns the function that removes it. */
  add(f: Listener<T>): () => void {
    this.listeners.push(f);
    return () => this.remove(f);
  }

  remove(f: Listener<T>): void {
    this.listeners = this.listeners.filter((x) => x !== f);
  }

  /** Calls every listener with `value`; a listener added or removed meanwhile counts from the next dispatch. */
  dispatch(value: T): void {
    for (const f of [...this.listeners]) {
      try {
        f(value);
      } catch (e) {
        this.report(e);
      }
    }
  }

  /** How many listeners are subscribed. */
  get size(): number {
    return this.listeners.length;
  }
}
