// Selecting and dragging controls in the viewport, in every posing mode,
// checked through the API's world pose (docs/EPHEMERAL.md, "Modes").

import { clickControl, dist, dragGizmo, expect, expectSelection, moved, poseDifference, setMode, sub, test } from './fixtures';

const kLeftArm = ['shoulder.L', 'upper_arm.L', 'forearm.L', 'hand.L'];
const kFar = ['hand.R', 'forearm.R', 'spine.003', 'spine', 'foot.R', 'spine.006'];
const kEps = 1e-6;

test('open the demo and select a control by clicking it', async ({ app: page, server, shots }) => {
  await shots.take('loaded');
  // The character is there: a canvas, joints and 159 control shapes.
  const info = await page.evaluate(() => ({
    controls: (window as any).rigel.app.nodes.controls.length,
    frames: (window as any).rigel.stats().frames,
  }));
  expect(info.controls).toBe(159);
  expect(info.frames).toBeGreaterThan(0);
  await expect(page.getByTestId('current-mode')).toContainText('Mode:');
  await expect(page.getByTestId('current-scope')).toContainText('character');

  await clickControl(page, 'hand.L_ctrl');
  await expectSelection(page, server, ['hand.L_ctrl']);
  await expect(page.getByTestId('selection')).toContainText('hand.L_ctrl');
  await shots.take('hand-selected');

  // Another click replaces the selection; a click on nothing clears it.
  await clickControl(page, 'spine.003_ctrl');
  await expectSelection(page, server, ['spine.003_ctrl']);
  const box = (await page.getByTestId('viewport-canvas').boundingBox())!;
  await page.mouse.click(box.x + 12, box.y + box.height - 12);
  await expectSelection(page, server, []);
  await shots.take('cleared');
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});

interface ModeCase {
  mode: string;
  control: string;
  check(before: Map<string, number[]>, after: Map<string, number[]>): void;
}

const cases: ModeCase[] = [
  {
    mode: 'forward',
    control: 'hand.L_ctrl',
    check(before, after) {
      const m = moved(before, after, ['hand.L', 'f_index.03.L', 'forearm.L', 'upper_arm.L', ...kFar]);
      expect(m['hand.L']).toBeGreaterThan(0.05);
      // The fingers follow rigidly: same translation as the hand.
      expect(dist(sub(after.get('f_index.03.L')!, before.get('f_index.03.L')!), sub(after.get('hand.L')!, before.get('hand.L')!))).toBeLessThan(1e-4);
      for (const n of ['forearm.L', 'upper_arm.L', ...kFar]) expect(m[n], `${n} stays`).toBeLessThan(kEps);
    },
  },
  {
    mode: 'pseudo-inverse',
    control: 'hand.L_ctrl',
    check(before, after) {
      const m = moved(before, after, [...kLeftArm, ...kFar]);
      expect(m['hand.L']).toBeGreaterThan(0.05);
      expect(m['forearm.L']).toBeGreaterThan(0.005);
      expect(m['forearm.L']).toBeLessThan(m['hand.L']!);
      expect(m['shoulder.L'], 'the chain top stays in place').toBeLessThan(kEps);
      for (const n of kFar) expect(m[n], `${n} stays`).toBeLessThan(kEps);
    },
  },
  {
    mode: 'inverse',
    control: 'hand.L_ctrl',
    check(before, after) {
      const m = moved(before, after, [...kLeftArm, ...kFar]);
      expect(m['hand.L']).toBeGreaterThan(0.05);
      expect(m['forearm.L']).toBeGreaterThan(0.001);
      for (const n of kFar) expect(m[n], `${n} stays`).toBeLessThan(kEps);
      // True IK keeps bone lengths exactly.
      for (const [a, b] of [['upper_arm.L', 'forearm.L'], ['forearm.L', 'hand.L']] as const) {
        expect(Math.abs(dist(after.get(a)!, after.get(b)!) - dist(before.get(a)!, before.get(b)!)), `${a}-${b} length`).toBeLessThan(1e-5);
      }
    },
  },
  {
    mode: 'suspended',
    control: 'forearm.L_ctrl',
    check(before, after) {
      const m = moved(before, after, ['forearm.L', 'hand.L', 'f_index.03.L', 'upper_arm.L', ...kFar]);
      expect(m['forearm.L']).toBeGreaterThan(0.05);
      // Children keep their world matrices.
      for (const n of ['hand.L', 'f_index.03.L', 'upper_arm.L', ...kFar]) expect(m[n], `${n} stays`).toBeLessThan(1e-5);
    },
  },
  {
    mode: 'magnet',
    control: 'hand.L_ctrl',
    check(before, after) {
      const m = moved(before, after, ['hand.L', 'forearm.L', 'foot.R', 'hand.R']);
      expect(m['hand.L']).toBeGreaterThan(0.05);
      // Each hop takes magnetFraction (0.65) of its driver's motion.
      const share = m['forearm.L']! / m['hand.L']!;
      expect(share).toBeGreaterThan(0.5);
      expect(share).toBeLessThan(0.8);
      expect(m['foot.R']! / m['hand.L']!).toBeLessThan(0.1);
      expect(m['hand.R']! / m['hand.L']!).toBeLessThan(0.5);
    },
  },
  {
    mode: 'body',
    control: 'hand.L_ctrl',
    check(before, after) {
      const d = sub(after.get('hand.L')!, before.get('hand.L')!);
      expect(Math.hypot(...d)).toBeGreaterThan(0.05);
      // Everything moves with the body pivot, rigidly.
      for (const n of ['spine', 'foot.R', 'hand.R', 'spine.006']) {
        expect(dist(sub(after.get(n)!, before.get(n)!), d), `${n} moves like the hand`).toBeLessThan(1e-4);
      }
    },
  },
];

// One scene for every mode: each drag is checked against the pose just
// before it, then undone (and the undo checked to restore it exactly).
test('drag with the gizmo in each mode: forward, pseudo-inverse, inverse, suspended, magnet, body', async ({ app: page, server, shots }) => {
  test.setTimeout(360_000);
  const uuids = await server.uuids();
  for (const c of cases) {
    await test.step(`${c.mode} on ${c.control}`, async () => {
      await setMode(page, server, c.mode);
      // Escape clears the selection (and the gizmo that covers the last control).
      await page.keyboard.press('Escape');
      await expectSelection(page, server, []);
      await clickControl(page, c.control);
      await expectSelection(page, server, [c.control]);
      const before = await server.worldPose();
      await dragGizmo(page, 'y', 70);
      await shots.take(`${c.mode}-dragged`);
      const after = await server.worldPose();
      c.check(before, after);
      // The viewport shows the pose the server holds.
      const shown = await page.evaluate((u) => (window as any).rigel.viewport.worldPosition(u), uuids.get(c.control));
      expect(dist(shown, after.get(c.control)!)).toBeLessThan(1e-4);
      // Back to the rest pose for the next mode.
      await page.getByTestId('undo').click();
      await expect.poll(async () => poseDifference(before, await server.worldPose())).toBe(0);
    });
  }
  const stats = await page.evaluate(() => (window as any).rigel.stats().drag);
  expect(stats.gestures).toBe(cases.length);
  expect(stats.failures).toBe(0);
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});

test('shift-click adds a control; dragging moves the whole selection; another tab follows', async ({ app: page, server, shots, context }) => {
  // A second tab on the same scene, following through GET /api/revision.
  const other = await context.newPage();
  await other.goto(server.pageUrl());
  await other.waitForFunction(() => (window as any).rigel?.isReady?.() === true, null, { timeout: 60_000 });
  await page.bringToFront();
  await setMode(page, server, 'forward');
  await clickControl(page, 'hand.L_ctrl');
  await clickControl(page, 'hand.R_ctrl', true);
  await expectSelection(page, server, ['hand.L_ctrl', 'hand.R_ctrl']);
  await expect(page.getByTestId('selection')).toContainText('hand.R_ctrl');
  await shots.take('two-selected');

  const before = await server.worldPose();
  await dragGizmo(page, 'y', 60);
  await shots.take('dragged');
  const after = await server.worldPose();
  const dl = sub(after.get('hand.L')!, before.get('hand.L')!);
  const dr = sub(after.get('hand.R')!, before.get('hand.R')!);
  expect(Math.hypot(...dl)).toBeGreaterThan(0.05);
  // Both are topmost grabbed controls: both take the same translation.
  expect(dist(dl, dr)).toBeLessThan(1e-4);
  for (const n of ['spine.003', 'forearm.L', 'forearm.R', 'foot.L']) {
    expect(dist(before.get(n)!, after.get(n)!), `${n} stays`).toBeLessThan(kEps);
  }

  // The other tab shows the new pose and selection without being touched.
  const handR = (await server.uuids()).get('hand.R')!;
  await expect
    .poll(async () => dist(await other.evaluate((u) => (window as any).rigel.viewport.worldPosition(u), handR), after.get('hand.R')!))
    .toBeLessThan(1e-5);
  await expect.poll(() => other.evaluate(() => (window as any).rigel.app.scene.selection.length)).toBe(2);
  await other.screenshot({ path: test.info().outputPath('other-tab.png') });
  await other.close();

  // Shift-click on a selected control takes it out of the selection.
  await clickControl(page, 'hand.L_ctrl', true);
  await expectSelection(page, server, ['hand.R_ctrl']);
});

test('undo and redo restore the pose exactly', async ({ app: page, server, shots }) => {
  await setMode(page, server, 'inverse');
  await clickControl(page, 'hand.L_ctrl');
  await expectSelection(page, server, ['hand.L_ctrl']);
  const before = await server.worldPose();
  await dragGizmo(page, 'y', 60);
  const after = await server.worldPose();
  expect(poseDifference(before, after)).toBeGreaterThan(0.05);
  await shots.take('dragged');

  await expect(page.getByTestId('undo')).toBeEnabled();
  await page.keyboard.press('Control+z');
  await expect.poll(async () => poseDifference(before, await server.worldPose())).toBe(0);
  await expect.poll(async () => (await server.get('/api/scene')).canRedo).toBe(true);
  // The viewport follows.
  const uuid = (await server.uuids()).get('hand.L')!;
  await expect
    .poll(async () => dist(await page.evaluate((u) => (window as any).rigel.viewport.worldPosition(u), uuid), before.get('hand.L')!))
    .toBeLessThan(1e-5);
  await shots.take('undone');

  await page.keyboard.press('Control+Shift+z');
  await expect.poll(async () => poseDifference(after, await server.worldPose())).toBe(0);
  await shots.take('redone');

  // The buttons do the same.
  await page.getByTestId('undo').click();
  await expect.poll(async () => poseDifference(before, await server.worldPose())).toBe(0);
  await page.getByTestId('redo').click();
  await expect.poll(async () => poseDifference(after, await server.worldPose())).toBe(0);
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});
