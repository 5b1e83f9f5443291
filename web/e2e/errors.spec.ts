// What the status bar says: errors in the user's words, cleared by a later
// success or dismissed, undo/redo with nothing to take as a state (not an
// error), and a server that goes away as one "connection lost" state that
// backs off and recovers when the server is back.

import { clickControl, dragGizmo, expect, expectSelection, setMode, settle, test } from './fixtures';

const errorsOf = (page: import('@playwright/test').Page): Promise<string[]> => page.evaluate(() => (window as any).rigel.errors as string[]);

test('a refused drag names the channel as the user knows it, and a later success clears the error', async ({ app: page, server }) => {
  // Inverse mode moves the arm's rotations: keyed at frame 0, a drag at
  // frame 10 is refused on a rotation channel.
  await setMode(page, server, 'inverse');
  await clickControl(page, 'hand.L_ctrl');
  await expectSelection(page, server, ['hand.L_ctrl']);
  await page.keyboard.press('s');
  await expect.poll(async () => (await server.get('/api/keys')).frames).toEqual([0]);
  await page.getByTestId('frame').fill('10');
  await page.getByTestId('frame').press('Enter');
  await expect.poll(async () => (await server.get('/api/scene')).frame).toBe(10);
  await page.getByTestId('frame').blur();

  await dragGizmo(page, 'y', 50);
  await expect(page.locator('#statusbar')).toHaveAttribute('data-state', 'error');
  const text = page.getByTestId('status-text');
  await expect(text).toContainText('409');
  await expect(text).toContainText('hand.L_ctrl.rotate is keyed');
  await expect(text).not.toContainText('rotateQuaternion');
  for (const e of await errorsOf(page)) expect(e).not.toMatch(/rotateQuaternion|[0-9a-f]{8}-[0-9a-f]{4}-/);

  // A later action that succeeds (a mode change says nothing) clears it.
  await setMode(page, server, 'forward');
  await expect(page.locator('#statusbar')).toHaveAttribute('data-state', 'info');
  await expect(text).not.toContainText('409');

  // Another refusal, dismissed by hand.
  await setMode(page, server, 'inverse');
  await dragGizmo(page, 'y', 40);
  await expect(page.locator('#statusbar')).toHaveAttribute('data-state', 'error');
  await page.getByTestId('status-dismiss').click();
  await expect(page.locator('#statusbar')).toHaveAttribute('data-state', 'info');
  await expect(text).toHaveText('');
  // The history keeps both.
  expect((await errorsOf(page)).filter((e) => e.includes('/api/drag'))).toHaveLength(2);
});

test('undo and redo with nothing to take are a quiet state, not an error', async ({ app: page, server }) => {
  // Nothing done yet: both buttons are off.
  await expect(page.getByTestId('undo')).toBeDisabled();
  await expect(page.getByTestId('redo')).toBeDisabled();
  await page.keyboard.press('Control+Shift+z');
  await expect(page.getByTestId('status-text')).toHaveText('Nothing to redo');
  await page.keyboard.press('Control+z');
  await expect(page.getByTestId('status-text')).toHaveText('Nothing to undo');
  await expect(page.locator('#statusbar')).toHaveAttribute('data-state', 'info');

  // A drag: undo on, redo still off; after undo, redo on and undo off.
  await setMode(page, server, 'forward');
  await clickControl(page, 'hand.L_ctrl');
  await expectSelection(page, server, ['hand.L_ctrl']);
  await dragGizmo(page, 'y', 50);
  await expect(page.getByTestId('undo')).toBeEnabled();
  await expect(page.getByTestId('redo')).toBeDisabled();
  await page.keyboard.press('Control+Shift+z');
  await expect(page.getByTestId('status-text')).toHaveText('Nothing to redo');
  await page.getByTestId('undo').click();
  await expect(page.getByTestId('redo')).toBeEnabled();
  await expect(page.getByTestId('undo')).toBeDisabled();

  // Another client takes the redo first: this tab's redo finds nothing (409), quietly.
  expect((await server.post('/api/redo')).status).toBe(200);
  await page.evaluate(() => (window as any).rigel.app.undo(true));
  await expect(page.getByTestId('status-text')).toContainText(/Nothing to redo|Redo/);
  await settle(page, server);
  expect(await errorsOf(page)).toEqual([]);
});

test('a server that goes away: one "connection lost" state, polls backing off, recovery when it is back', async ({ app: page, server }) => {
  test.setTimeout(240_000);
  await server.kill();
  const bar = page.locator('#statusbar');
  await expect(bar).toHaveAttribute('data-state', 'offline');
  await expect(page.getByTestId('status-text')).toContainText('Connection lost');
  // Retries back off: wait for five of them (state, not time).
  await expect.poll(() => page.evaluate(() => (window as any).rigel.app.retries.length), { timeout: 60_000 }).toBeGreaterThanOrEqual(5);
  const retries = (await page.evaluate(() => (window as any).rigel.app.retries)) as number[];
  // The gaps double: 0.5 s, 1 s, 2 s, 4 s (then 4 s each). A loaded
  // machine only makes a timer late, so each gap is at least its nominal.
  const gaps = retries.slice(1, 5).map((t, i) => t - retries[i]!);
  [500, 1000, 2000, 4000].forEach((nominal, i) => expect(gaps[i]!, `retry gaps ${gaps.join(', ')} ms`).toBeGreaterThanOrEqual(nominal * 0.95));
  // Actions while the server is gone add no error of their own.
  await page.keyboard.press('2');
  await page.keyboard.press('Escape');
  await expect.poll(() => page.evaluate(() => (window as any).rigel.app.api.pending)).toBe(0);
  const errors = await errorsOf(page);
  expect(errors, errors.join('\n')).toHaveLength(1);
  expect(errors[0]).toContain('Connection lost');
  await expect(bar).toHaveAttribute('data-state', 'offline');

  // Back on the same port (a new scene, its revisions start again).
  await server.restart();
  await expect(page.getByTestId('status-text')).toHaveText('Connection restored', { timeout: 60_000 });
  await expect(bar).toHaveAttribute('data-state', 'info');
  await settle(page, server);
  // The page works again against the new server.
  await setMode(page, server, 'forward');
  await clickControl(page, 'hand.L_ctrl');
  await expectSelection(page, server, ['hand.L_ctrl']);
  expect(await errorsOf(page)).toHaveLength(1);
});
