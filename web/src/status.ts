// The status bar: the last message, errors in red, and a history of every
// error (hover the bar or read window.rigel.errors). No error of the API is
// ever dropped: the client reports each failure here before rejecting.

import { ApiError } from './api';

export interface StatusEntry {
  time: number;
  level: 'info' | 'error';
  text: string;
}

export class StatusBar {
  readonly history: StatusEntry[] = [];
  readonly errors: string[] = [];
  private readonly text: HTMLElement;
  private readonly count: HTMLElement;

  constructor(private readonly el: HTMLElement) {
    this.el.innerHTML = '';
    this.text = document.createElement('span');
    this.text.className = 'status-text';
    this.text.dataset.testid = 'status-text';
    this.count = document.createElement('span');
    this.count.className = 'status-count';
    const clear = document.createElement('button');
    clear.className = 'link';
    clear.textContent = 'clear';
    clear.title = 'Clear the status bar';
    clear.addEventListener('click', () => this.info(''));
    this.el.append(this.text, this.count, clear);
  }

  info(text: string): void {
    this.push('info', text);
  }

  error(text: string): void {
    this.errors.push(text);
    this.push('error', text);
    console.warn('[rigel]', text);
  }

  /** Any thrown value: API errors are already reported by the client. */
  caught(e: unknown): void {
    if (e instanceof ApiError) return;
    this.error(e instanceof Error ? e.message : String(e));
  }

  private push(level: 'info' | 'error', text: string): void {
    this.history.push({ time: Date.now(), level, text });
    if (this.history.length > 200) this.history.shift();
    this.text.textContent = text;
    this.el.classList.toggle('error', level === 'error' && text.length > 0);
    this.count.textContent = this.errors.length ? `${this.errors.length} error${this.errors.length > 1 ? 's' : ''}` : '';
    this.el.title = this.history
      .slice(-15)
      .map((h) => `${new Date(h.time).toLocaleTimeString()} ${h.level === 'error' ? '✖' : '·'} ${h.text}`)
      .join('\n');
  }
}

let bar: StatusBar | null = null;

export function setStatusBar(b: StatusBar): void {
  bar = b;
}

export function status(): StatusBar {
  if (!bar) throw new Error('status bar not set up');
  return bar;
}

/** Runs a promise for its effect; a failure goes to the status bar (once). */
export function run(p: Promise<unknown>): void {
  p.catch((e: unknown) => {
    if (bar) bar.caught(e);
    else console.error(e);
  });
}
