// Motion trails and ghosts: the selected hand control's trail over the
// playback range drawn from the server's evaluated curves, its keys
// marked, following a key moved; ghosts of the skeleton before and after
// the current frame, following the time, and at the keys; both on while a
// drag runs.

import { clickControl, dragGizmo, expect, expectSelection, goToFrame, setMode, settle, test, type RigelServer } from './fixtures';
import type { Page } from '@playwright/test';

async function drawn(page: Page, server: RigelServer): Promise<{ trails: { control: string; points: number[][]; keys: number[] }[]; ghosts: number[]; bones: number }> {
  await settle(page, server);
  return page.evaluate(() => (window as any).rigel.overlays.state());
}

test('motion trail and ghosts follow keys, time and drags', async ({ app: page, server, shots }) => {
  await setMode(page, server, 'forward');
  await clickControl(page, 'hand.L_ctrl');
  await expectSelection(page, server, ['hand.L_ctrl']);
  await goToFrame(page, server, 0);
  await page.keyboard.press('s');
  await goToFrame(page, server, 10);
  const hand = (await server.uuids()).get('hand.L_ctrl')!;
  const set = await server.post('/api/channel-values', { controls: [hand], attrs: ['translateY'], value: 0.2 });
  expect(set.status, JSON.stringify(set.body)).toBe(200);
  await page.getByTestId('set-key').click();
  await expect.poll(async () => (await server.get('/api/keys')).frames).toEqual([0, 10]);

  // The trail: the server's, over the range the timeline plays, keys marked.
  await page.keyboard.press('t');
  await expect(page.getByTestId('toggle-trails')).toHaveClass(/active/);
  await expect.poll(async () => (await drawn(page, server)).trails.map((t) => t.keys)).toEqual([[0, 10]]);
  const want = await server.get(`/api/trails?controls=${hand}&first=0&last=10`);
  const trail = (await drawn(page, server)).trails[0]!;
  expect(trail.control).toBe('hand.L_ctrl');
  expect(trail.points).toEqual(want.trails[0].points);
  expect(Math.abs(trail.points[10]![1]! - trail.points[0]![1]!)).toBeGreaterThan(0.01);

  // Ghosts around the current frame (10): 4, 6, 8 before, 12, 14, 16 after.
  await page.keyboard.press('o');
  await expect.poll(async () => (await drawn(page, server)).ghosts).toEqual([4, 6, 8, 12, 14, 16]);
  expect((await drawn(page, server)).bones).toBeGreaterThan(100);
  await shots.take('trail-and-ghosts');
  // They follow the time.
  await goToFrame(page, server, 6);
  await expect.poll(async () => (await drawn(page, server)).ghosts).toEqual([0, 2, 4, 8, 10, 12]);

  // A key moved: the trail follows (its key at 14 now).
  const moved = await server.post('/api/channel-keys', { controls: [hand], moveTo: 14, from: 10 });
  expect(moved.status, JSON.stringify(moved.body)).toBe(200);
  await expect.poll(async () => (await drawn(page, server)).trails.map((t) => t.keys)).toEqual([[0, 14]]);

  // On while dragging: a drag at a key lands in it and the trail follows.
  await goToFrame(page, server, 14);
  const before = (await drawn(page, server)).trails[0]!.points;
  await dragGizmo(page, 'y', 60);
  await expect.poll(async () => JSON.stringify((await drawn(page, server)).trails[0]!.points) !== JSON.stringify(before)).toBe(true);
  expect((await drawn(page, server)).ghosts).toEqual([8, 10, 12, 16, 18, 20]);
  await shots.take('trail-after-drag');

  // O again: ghosts at the keys (0 and 14); again: off, with T nothing drawn.
  await page.keyboard.press('o');
  await expect(page.getByTestId('toggle-ghosts')).toContainText('keys');
  await expect.poll(async () => (await drawn(page, server)).ghosts).toEqual([0, 14]);
  await page.keyboard.press('t');
  await page.keyboard.press('o');
  await expect.poll(async () => (await drawn(page, server)).trails.length + (await drawn(page, server)).ghosts.length).toBe(0);
});
