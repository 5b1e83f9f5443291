// The status bar: the last message, errors in red, and a history of every
// error (hover the bar or read window.rigel.errors). No error of the API is
// ever dropped: the client reports each failure here before rejecting.
//
// An error stays shown until the user dismisses it (×) or a later action
// succeeds (clearError). A lost connection is one state ("connection lost,
// retrying"), recorded once per outage, that replaces the message until
// the server answers again.

import { ApiError } from './api';

export interface StatusEntry {
  time: number;
  level: 'info' | 'error';
  text: string;
}

export type StatusState = 'info' | 'error' | 'offline';

export class StatusBar {
  readonly history: StatusEntry[] = [];
  readonly errors: string[] = [];
  state: StatusState = 'info';
  /** Puts a message in the user's words (names.ts's userText, set by main.ts). */
  rename: (text: string) => string = (t) => t;
  private readonly text: HTMLElement;
  private readonly count: HTMLElement;
  private isOffline = false;

  constructor(private readonly el: HTMLElement) {
    this.el.innerHTML = '';
    this.text = document.createElement('span');
    this.text.className = 'status-text';
    this.text.dataset.testid = 'status-text';
    this.count = document.createElement('span');
    this.count.className = 'status-count';
    const clear = document.createElement('button');
    clear.className = 'link';
    clear.textContent = '×';
    clear.title = 'Dismiss the message';
    clear.dataset.testid = 'status-dismiss';
    clear.addEventListener('click', () => this.dismiss());
    this.el.append(this.text, this.count, clear);
    this.setState('info');
  }

  info(text: string): void {
    this.push('info', this.rename(text));
  }

  error(message: string): void {
    const text = this.rename(message);
    this.errors.push(text);
    this.push('error', text);
    console.warn('[rigel]', text);
  }

  /** Any thrown value: API errors are already reported by the client. */
  caught(e: unknown): void {
    if (e instanceof ApiError) return;
    this.error(e instanceof Error ? e.message : String(e));
  }

  /** A later action succeeded: the error shown (if any) is no longer current. */
  clearError(): void {
    if (this.state === 'error') this.show('info', '');
  }

  /** The × of the bar: the message goes (the history keeps it). */
  dismiss(): void {
    if (this.state !== 'offline') this.show('info', '');
  }

  /** The server stopped answering (true) or answers again (false). */
  offline(on: boolean, detail = ''): void {
    if (on === this.isOffline) return;
    this.isOffline = on;
    if (on) {
      const text = `Connection lost: retrying${detail ? ` (${detail})` : ''}…`;
      this.errors.push(text);
      this.record('error', text);
      console.warn('[rigel]', text);
      this.show('offline', text);
    } else {
      this.push('info', 'Connection restored');
    }
  }

  private push(level: 'info' | 'error', text: string): void {
    this.record(level, text);
    // While the connection is lost that state stays shown; the rest goes to the history.
    if (!this.isOffline) this.show(level, text);
  }

  private record(level: 'info' | 'error', text: string): void {
    this.history.push({ time: Date.now(), level, text });
    if (this.history.length > 200) this.history.shift();
    this.count.textContent = this.errors.length ? `${this.errors.length} error${this.errors.length > 1 ? 's' : ''}` : '';
    this.el.title = this.history
      .slice(-15)
      .map((h) => `${new Date(h.time).toLocaleTimeString()} ${h.level === 'error' ? '✖' : '·'} ${h.text}`)
      .join('\n');
  }

  private show(state: StatusState, text: string): void {
    this.text.textContent = text;
    this.setState(text.length ? state : 'info');
  }

  private setState(state: StatusState): void {
    this.state = state;
    this.el.dataset.state = state;
    this.el.classList.toggle('error', state === 'error');
    this.el.classList.toggle('offline', state === 'offline');
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
