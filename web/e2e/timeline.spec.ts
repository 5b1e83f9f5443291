// The timeline: a playback range set in its fields (saved with the scene,
// undone), key ticks clicked (go to the frame), dragged (retime: the pose
// moves with the key) and Alt-dragged (copy), each one undo step, and
// previous / next key.

import { clickControl, dist, expect, expectSelection, goToFrame, setMode, settle, test, type RigelServer } from './fixtures';
import type { Page } from '@playwright/test';

async function keyFrames(server: RigelServer): Promise<number[]> {
  return (await server.get('/api/keys')).frames;
}

/** Drags the tick of frame `from` to where frame `to` lies on the track (Alt held to copy). */
async function dragTick(page: Page, server: RigelServer, from: number, to: number, alt = false): Promise<void> {
  await settle(page, server);
  const tick = page.getByTestId(`tick-${from}`);
  const box = (await tick.boundingBox())!;
  const track = (await page.getByTestId('key-ticks').boundingBox())!;
  const range = (await page.evaluate(() => (window as any).rigel.timeline.range())) as [number, number];
  const x = track.x + 7 + ((to - range[0]) / (range[1] - range[0])) * (track.width - 14);
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  if (alt) await page.keyboard.down('Alt');
  for (let i = 1; i <= 6; ++i) await page.mouse.move(box.x + box.width / 2 + ((x - box.x - box.width / 2) * i) / 6, box.y + box.height / 2);
  await page.mouse.up();
  if (alt) await page.keyboard.up('Alt');
}

test('timeline: playback range, tick click, retime and copy by drag, previous and next key', async ({ app: page, server, shots }) => {
  await setMode(page, server, 'forward');
  await clickControl(page, 'hand.L_ctrl');
  await expectSelection(page, server, ['hand.L_ctrl']);
  await goToFrame(page, server, 0);
  await page.keyboard.press('s');
  await expect.poll(() => keyFrames(server)).toEqual([0]);
  const rest = (await server.worldPose()).get('hand.L')!;
  // A second key at 10 with the hand raised (set through the channel box's API, as a drag would).
  await goToFrame(page, server, 10);
  const hand = (await server.uuids()).get('hand.L_ctrl')!;
  const set = await server.post('/api/channel-values', { controls: [hand], attrs: ['translateY'], value: 0.2 });
  expect(set.status, JSON.stringify(set.body)).toBe(200);
  await page.getByTestId('set-key').click();
  await expect.poll(() => keyFrames(server)).toEqual([0, 10]);
  await expect(page.getByTestId('fps')).toHaveText('24 fps');

  // The playback range from its fields: saved on the scene, the slider follows, undo takes it back.
  await page.getByTestId('range-first').fill('0');
  await page.getByTestId('range-last').fill('40');
  await page.getByTestId('range-last').press('Enter');
  await expect.poll(async () => (await server.get('/api/scene')).playbackRange).toEqual([0, 40]);
  await expect(page.getByTestId('frame-slider')).toHaveAttribute('max', '40');
  await page.getByTestId('range-last').fill('-5');
  await page.getByTestId('range-last').press('Enter');
  await expect(page.locator('#statusbar')).toContainText('before the first');
  expect((await server.get('/api/scene')).playbackRange).toEqual([0, 40]);
  await shots.take('timeline-range');

  // Click a tick: the frame goes there.
  await goToFrame(page, server, 3);
  await settle(page, server);
  await page.getByTestId('tick-10').click();
  await expect.poll(async () => (await server.get('/api/scene')).frame).toBe(10);
  const raised = (await server.worldPose()).get('hand.L')!;
  expect(dist(raised, rest)).toBeGreaterThan(1e-3);

  // Drag the tick of 10 to 20: the keys move, the raised pose is at 20 now, not at 10.
  await dragTick(page, server, 10, 20);
  await expect.poll(() => keyFrames(server)).toEqual([0, 20]);
  await goToFrame(page, server, 20);
  expect(dist((await server.worldPose()).get('hand.L')!, raised)).toBeLessThan(1e-6);
  await expect(page.getByTestId('tick-20')).toBeVisible();
  await shots.take('timeline-retimed');
  // One undo step.
  await page.getByTestId('undo').click();
  await expect.poll(() => keyFrames(server)).toEqual([0, 10]);

  // Alt-drag copies: the key at 10 stays, a copy lands at 30.
  await dragTick(page, server, 10, 30, true);
  await expect.poll(() => keyFrames(server)).toEqual([0, 10, 30]);
  await goToFrame(page, server, 30);
  expect(dist((await server.worldPose()).get('hand.L')!, raised)).toBeLessThan(1e-6);

  // Previous / next key.
  await goToFrame(page, server, 12);
  await page.getByTestId('prev-key').click();
  await expect.poll(async () => (await server.get('/api/scene')).frame).toBe(10);
  await settle(page, server); // the page's own frame and keys are the server's again
  await page.getByTestId('next-key').click();
  await expect.poll(async () => (await server.get('/api/scene')).frame).toBe(30);

  // The range undoes too (after the key edits above, in order).
  await page.getByTestId('undo').click(); // the copy
  await page.getByTestId('undo').click(); // the range
  await expect.poll(async () => (await server.get('/api/scene')).playbackRange).toBeNull();
});
