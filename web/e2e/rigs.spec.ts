// The Rig Manager: add a rig from a definition, step its build, notice the
// definition changed on disk (red warning), update, remove.

import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { expect, settle, test } from './fixtures';

// The biped drives the joints itself: no ephemeral controls on this character.
test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

test('Rig Manager: add, step, out of date, update, remove', async ({ app: page, server, shots }) => {
  await page.getByTestId('tab-rigs').click();
  await expect(page.getByTestId('rig-list')).toContainText('No rig');
  await shots.take('empty');

  await page.getByTestId('rig-add-path').fill('examples/biped.rig.xml');
  await page.getByTestId('rig-add').click();
  const row = page.getByTestId('rig-hero');
  await expect(row).toBeVisible();
  await expect(row).toContainText('v1.0');
  await expect(row).toContainText('biped.rig.xml');
  await expect(row).not.toHaveClass(/out-of-date/);
  await expect(page.getByTestId('rig-warning')).toHaveCount(0);
  const rigs = (await server.get('/api/rigs')).rigs;
  expect(rigs.map((r: any) => r.name)).toEqual(['hero']);
  const steps: number = rigs[0].steps;
  expect(rigs[0].buildPosition).toBe(steps);
  // The viewport now draws the rig's controls too.
  await expect
    .poll(() => page.evaluate(() => (window as any).rigel.app.nodes.controls.filter((c: any) => c.rig === 'hero').length))
    .toBeGreaterThan(10);
  await shots.take('added');

  // Build stepping.
  await expect(page.getByTestId('step-position')).toHaveText(`${steps} / ${steps}`);
  await page.getByTestId('step-back').click();
  await expect(page.getByTestId('step-position')).toHaveText(`${steps - 1} / ${steps}`);
  await expect.poll(async () => (await server.get('/api/rigs')).rigs[0].buildPosition).toBe(steps - 1);
  await shots.take('stepped-back');
  await page.getByTestId('step-forward').click();
  await expect(page.getByTestId('step-position')).toHaveText(`${steps} / ${steps}`);

  // Feature toggles: stretch off redoes the build without it, then on again.
  const stretch = page.getByTestId('rig-feature-stretch');
  await expect(stretch).toBeChecked();
  await stretch.uncheck();
  await expect
    .poll(async () => (await server.get('/api/rigs')).rigs[0].features.find((f: any) => f.feature === 'stretch').enabled)
    .toBe(false);
  await shots.take('stretch-off');
  await page.getByTestId('rig-feature-stretch').check();
  await expect
    .poll(async () => (await server.get('/api/rigs')).rigs[0].features.find((f: any) => f.feature === 'stretch').enabled)
    .toBe(true);

  // A newer definition on disk: the rig turns red with a warning.
  const file = join(server.root, 'examples/biped.rig.xml');
  const xml = readFileSync(file, 'utf8');
  const newer = xml
    .replace('<rig name="hero" version="1.0">', '<rig name="hero" version="1.1">')
    .replace(
      /(<component type="eye" name="eyes" side="C" version=")1\.0(")/,
      '$11.1$2',
    )
    .replace('<param name="aimDistance" value="0.4"/>', '<param name="aimDistance" value="0.5"/>');
  expect(newer).not.toEqual(xml);
  writeFileSync(file, newer);
  // Noticed by the Rig Manager's periodic refetch (a file changes no revision).
  await expect(row).toHaveClass(/out-of-date/);
  await expect(page.getByTestId('rig-warning')).toBeVisible();
  await expect(page.getByTestId('rig-warning')).toContainText('1.1');
  await expect(page.getByTestId('rig-update')).toHaveClass(/danger/);
  // Per component: the eyes changed (v1.1 on disk), the hip did not.
  await expect(page.getByTestId('rig-component-eyes')).toHaveAttribute('data-state', 'changed');
  await expect(page.getByTestId('rig-component-eyes')).toContainText('→ v1.1');
  await expect(page.getByTestId('rig-component-hip')).toHaveAttribute('data-state', 'current');
  await expect(page.getByTestId('rig-warning')).toContainText('changed: eyes');
  const warnColor = await row.evaluate((el) => getComputedStyle(el).borderTopColor);
  expect(warnColor).toBe('rgb(255, 92, 92)');
  await shots.take('out-of-date');

  // Update, keeping the world positions of keys.
  await page.getByTestId('rig-keep-world').check();
  await page.getByTestId('rig-update').click();
  await expect(row).not.toHaveClass(/out-of-date/);
  await expect(row).toContainText('v1.1');
  await expect(page.getByTestId('rig-warning')).toHaveCount(0);
  const updated = (await server.get('/api/rigs')).rigs[0];
  expect(updated.version).toBe('1.1');
  expect(updated.outOfDate).toBe(false);
  await expect(page.getByTestId('rig-component-eyes')).toHaveAttribute('data-state', 'current');
  await shots.take('updated');

  // Rig edit mode on the built rig, and back out of it.
  await page.getByTestId('rig-enter-edit').click();
  await expect.poll(async () => (await server.get('/api/rigs')).rigs[0].editMode).toBe(true);
  await expect(row).toContainText('EDIT');
  await shots.take('edit-mode');
  await page.getByTestId('rig-leave-edit').click();
  await expect.poll(async () => (await server.get('/api/rigs')).rigs[0].editMode).toBe(false);

  // Remove.
  await page.getByTestId('rig-remove').click();
  await expect(page.getByTestId('rig-list')).toContainText('No rig');
  expect((await server.get('/api/rigs')).rigs).toEqual([]);
  await expect
    .poll(() => page.evaluate(() => (window as any).rigel.app.nodes.controls.filter((c: any) => c.rig === 'hero').length))
    .toBe(0);
  await shots.take('removed');
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});

test('Rig Manager: a missing definition is reported in the status bar', async ({ app: page }) => {
  await page.getByTestId('rig-add-path').fill('examples/nope.rig.xml');
  await page.getByTestId('rig-add').click();
  await expect(page.locator('#statusbar')).toHaveClass(/error/);
  await expect(page.getByTestId('status-text')).toContainText('/api/rigs/add');
  // Paths that leave the root are refused (400).
  await page.getByTestId('rig-add-path').fill('../../etc/passwd');
  await page.getByTestId('rig-add').click();
  await expect(page.getByTestId('status-text')).toContainText('400');
});

// The page drops a removed rig's nodes even when an older refresh comes back
// after the removal's (the nodes answer of a refresh that started before the
// Remove is held until the Remove's own refresh could have been applied).
test('Rig Manager: a removed rig leaves no control behind, whatever order refreshes come back in', async ({ app: page, server }) => {
  await page.getByTestId('rig-add-path').fill('examples/biped.rig.xml');
  await page.getByTestId('rig-add').click();
  await expect(page.getByTestId('rig-hero')).toBeVisible();
  const heroControls = () => page.evaluate(() => (window as any).rigel.app.nodes.controls.filter((c: any) => c.rig === 'hero').length);
  await expect.poll(heroControls).toBeGreaterThan(10);
  await settle(page, server);

  // The next GET /api/nodes is answered now (with the rig) but delivered late.
  let release!: () => void;
  const released = new Promise<void>((r) => (release = r));
  let held = false;
  let heldSeen!: () => void;
  const heldArrived = new Promise<void>((r) => (heldSeen = r));
  await page.route('**/api/nodes', async (route) => {
    if (held) return route.continue();
    held = true;
    const answer = await route.fetch();
    heldSeen();
    await released;
    await route.fulfill({ response: answer });
  });
  // A refresh (stepping refreshes everything) whose nodes answer is held...
  await page.getByTestId('step-back').click();
  await heldArrived;
  // ...then Remove, whose refresh the page may run (or queue) meanwhile.
  await page.getByTestId('rig-remove').click();
  await expect.poll(async () => (await server.get('/api/rigs')).rigs).toEqual([]);
  // Let the held answer go once nothing else is left to come back: the
  // Remove's refresh applied (a page that runs refreshes side by side) or
  // queued behind the held one (a page that runs them one at a time).
  await page.waitForFunction(() => {
    const app = (window as any).rigel.app;
    const applied = app.rigs.length === 0 && app.nodes.controls.every((c: any) => c.rig !== 'hero');
    const queued = app.api.pending === 1 && app.api.pendingWrites === 0;
    return applied || queued;
  });
  release();
  await settle(page, server);
  expect(await heroControls()).toBe(0);
  await expect(page.getByTestId('rig-list')).toContainText('No rig');
  const shown = await page.evaluate(() => [...(window as any).rigel.viewport.controlNames().values()].filter((n: string) => n.startsWith('hero_')).length);
  expect(shown, 'the viewport draws no control of the removed rig').toBe(0);
  await page.unroute('**/api/nodes');
});
