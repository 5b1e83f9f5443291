// Keys on two frames, playback between them, the refusal of a drag off a
// key without auto-key (shown in the status bar) and auto-key.

import { clickControl, dist, dragGizmo, expect, expectSelection, goToFrame, setMode, settle, test, type RigelServer } from './fixtures';


async function handAt(server: RigelServer): Promise<number[]> {
  return (await server.worldPose()).get('hand.L')!;
}

test('set keys on two frames and play between them', async ({ app: page, server, shots }) => {
  await setMode(page, server, 'forward');
  await clickControl(page, 'hand.L_ctrl');
  await expectSelection(page, server, ['hand.L_ctrl']);
  await goToFrame(page, server, 0);

  // Key at 0 (S).
  await page.keyboard.press('s');
  await expect.poll(async () => (await server.get('/api/keys')).frames).toEqual([0]);
  await expect(page.getByTestId('key-ticks').locator('.tick')).toHaveCount(1);
  await shots.take('key-0');

  // Off a key, with auto-key off, a drag is refused: the status bar says so.
  await goToFrame(page, server, 10);
  const p0 = await handAt(server);
  await dragGizmo(page, 'y', 50);
  await expect(page.locator('#statusbar')).toHaveClass(/error/);
  const errors = (await page.evaluate(() => (window as any).rigel.errors)) as string[];
  expect(errors.some((e) => e.includes('/api/drag') && e.includes('409')), errors.join('\n')).toBe(true);
  expect(dist(await handAt(server), p0)).toBeLessThan(1e-9);
  await shots.take('refused-off-key');

  // Key at 10, then the drag lands in that key.
  await page.getByTestId('set-key').click();
  await expect.poll(async () => (await server.get('/api/keys')).frames).toEqual([0, 10]);
  await dragGizmo(page, 'y', 70);
  const p10 = await handAt(server);
  expect(dist(p10, p0)).toBeGreaterThan(0.05);
  await expect(page.getByTestId('key-ticks').locator('.tick')).toHaveCount(2);
  await expect(page.getByTestId('key-frames')).toContainText('0, 10');
  await shots.take('key-10');

  // Frame 0 still holds the first pose.
  await goToFrame(page, server, 0);
  expect(dist(await handAt(server), p0)).toBeLessThan(1e-6);

  // Play: the frame advances and the pose changes between the keys.
  const uuid = (await server.uuids()).get('hand.L')!;
  const seen: number[][] = [];
  await page.keyboard.press('Space');
  await expect(page.getByTestId('play')).toHaveClass(/active/);
  // Sample the shown pose until the timeline has played frame 8 and three
  // different poses were seen (playing loops over the keyed range, so a
  // fast machine that plays 8 frames between two samples sees more later).
  const distinctSeen = (): number => new Set(seen.map((p) => p.map((v) => v.toFixed(5)).join(','))).size;
  await expect
    .poll(
      async () => {
        seen.push(await page.evaluate((u) => (window as any).rigel.viewport.worldPosition(u), uuid));
        const played = (await page.evaluate(() => (window as any).rigel.timeline.playedFrames)) as number[];
        return played.includes(8) && distinctSeen() >= 3;
      },
      { timeout: 60_000, message: 'playing reaches frame 8, showing the pose change' },
    )
    .toBe(true);
  await shots.take('playing');
  await page.keyboard.press('Space');
  await expect(page.getByTestId('play')).not.toHaveClass(/active/);
  // The step in flight when playing stopped lands before the next move.
  await settle(page, server);
  const played = (await page.evaluate(() => (window as any).rigel.timeline.playedFrames)) as number[];
  expect(played.slice(0, 8)).toEqual([1, 2, 3, 4, 5, 6, 7, 8]);
  expect(distinctSeen(), 'the viewport showed the pose changing while playing').toBeGreaterThanOrEqual(3);

  // Between the keys the pose lies between the keyed poses.
  await goToFrame(page, server, 5);
  const p5 = await handAt(server);
  expect(dist(p5, p0)).toBeGreaterThan(1e-3);
  expect(dist(p5, p10)).toBeGreaterThan(1e-3);
  expect(dist(p0, p5) + dist(p5, p10)).toBeLessThan(dist(p0, p10) * 1.5);
  await shots.take('frame-5');

  // Auto-key: a drag off a key keys the character there first.
  await goToFrame(page, server, 20);
  await page.getByTestId('auto-key').check();
  await expect.poll(async () => (await server.get('/api/scene')).autoKey).toBe(true);
  await dragGizmo(page, 'y', 40);
  await expect.poll(async () => (await server.get('/api/keys')).frames).toEqual([0, 10, 20]);
  await expect(page.getByTestId('key-ticks').locator('.tick')).toHaveCount(3);
  await shots.take('auto-key');

  // Delete key (Shift+S) at 20.
  await page.keyboard.press('Shift+S');
  await expect.poll(async () => (await server.get('/api/keys')).frames).toEqual([0, 10]);
});
